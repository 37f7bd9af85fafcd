#include "animanifold/stitch.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_stitch(py::module_& m) {
  m.def("stitch",
        [](PointsRef frames, SimplicesRef faces, const Eigen::VectorXd& times, VertexAttributes vertex_attributes,
           SimplexAttributes face_attributes) {
          StitchInput in{frames, faces, times, std::move(vertex_attributes), std::move(face_attributes)};
          py::gil_scoped_release release;
          return std::make_shared<Complex>(stitch(in));
        },
        py::arg("frames"), py::arg("faces"), py::arg("times"), py::arg("vertex_attributes") = VertexAttributes{},
        py::arg("face_attributes") = SimplexAttributes{},
        "Keyframes ((m*k) by d, keyframe-major) with shared faces → animation manifold (a Complex).");
}

}  // namespace animanifold::bindings
