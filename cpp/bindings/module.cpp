#include "bindings.hpp"

namespace animanifold::bindings {

PYBIND11_MODULE(_core, m) {
  m.doc() = "animanifold's native core: animation manifolds as simplicial complexes";
  // Test-only entry points, kept out of the package's API.
  py::module_ testing = m.def_submodule("_testing", "Entry points used only by the tests and benchmarks.");
  bind_errors(m);
  bind_errors_testing(testing);
  bind_complex(m, testing);
  bind_stitch(m);
  bind_slice(m, testing);
  bind_io(m);
  bind_delaunay(m, testing);
  bind_morph(m, testing);
  bind_refine(m, testing);
  bind_subdivide(m);
  bind_skeleton(m);
  bind_laplacian(m, testing);
  bind_hole_space(m);
  bind_memory(m);
  bind_threads(m, testing);
}

}  // namespace animanifold::bindings
