#include "animanifold/memory_limit.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_memory(py::module_& m) {
  m.def("set_memory_limit", &set_memory_limit, py::arg("bytes"),
        "Sets the most memory one core call may estimate it needs (stitch, subdivide, refine, frame "
        "subdivision); None returns to the default, half of the available memory. Raises InputError for 0.");
  m.def("memory_limit", py::overload_cast<>(&memory_limit),
        "The memory limit in force, in bytes: the one set, else half of the available memory now.");
  m.def("memory_limit_setting", &memory_limit_setting, "The memory limit set, or None when the default applies.");
  m.def("available_memory", [] { return available_memory(); },
        "The memory the system can give without swapping, in bytes: MemAvailable, or what the process's "
        "cgroups still allow where that is less.");
}

}  // namespace animanifold::bindings
