#include "bindings.hpp"

#include "animanifold/errors.hpp"

namespace animanifold::bindings {

PYBIND11_MODULE(_core, m) {
  m.doc() = "animanifold's native core: animation manifolds as simplicial complexes";
  // std::invalid_argument (InputError) already becomes ValueError; file
  // problems become OSError, as Python users expect of files.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IOError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });
  bind_complex(m);
  bind_stitch(m);
  bind_slice(m);
  bind_io(m);
  bind_delaunay(m);
  bind_morph(m);
  bind_refine(m);
  bind_subdivide(m);
  bind_skeleton(m);
  bind_laplacian(m);
  bind_hole_space(m);
}

}  // namespace animanifold::bindings
