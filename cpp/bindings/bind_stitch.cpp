#include "animanifold/stitch.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"

namespace animanifold::bindings {

void bind_stitch(py::module_& m) {
  m.def("stitch",
        [](PointsRef frames, SimplicesRef faces, const Eigen::VectorXd& times, VertexAttributes vertex_attributes,
           SimplexAttributes face_attributes, IndicesRef vertex_order, const py::object& progress,
           const py::object& interrupted) {
          StitchInput in{frames, faces, times, std::move(vertex_attributes), std::move(face_attributes),
                         IndexVector(vertex_order)};
          const Interrupter interrupter = interrupter_from(progress, interrupted);
          return without_gil([&] { return std::make_shared<Complex>(stitch(in, interrupter)); });
        },
        py::arg("frames"), py::arg("faces"), py::arg("times"), py::arg("vertex_attributes") = VertexAttributes{},
        py::arg("face_attributes") = SimplexAttributes{}, py::arg("vertex_order") = IndexVector{},
        py::kw_only(), py::arg("progress") = py::none(), py::arg("interrupted") = py::none(),
        (std::string("Keyframes ((m*k) by d, keyframe-major) with shared faces → animation manifold (a Complex); "
                     "raises InputError naming the keyframe, vertex or face that is wrong, MemoryLimitError when the "
                     "manifold would not fit the memory limit.") +
         kInterrupterDoc)
            .c_str());
}

}  // namespace animanifold::bindings
