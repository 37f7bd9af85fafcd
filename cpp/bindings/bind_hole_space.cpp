#include "animanifold/hole_space.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"

#include <string>

namespace animanifold::bindings {

namespace {

// CGAL runs in a child process (hole_space.hpp); the docstring sentence of the Booleans.
constexpr const char* kBooleanInterrupterDoc =
    " CGAL runs in a child process: `interrupted()` returning True, or Ctrl-C, stops it with Cancelled, and "
    "one that runs far past its size's time (a minute and more) ends in TimeLimitError.";

}  // namespace

void bind_hole_space(py::module_& m) {
  m.def(
      "hole_space",
      [](PointsRef V, SimplicesRef F, const py::object& interrupted) {
        const Interrupter interrupter = interrupter_from(py::none(), interrupted);
        Solid s = without_gil([&] { return hole_space(V, F, interrupter); });
        return py::make_tuple(std::move(s.vertices), std::move(s.faces));
      },
      py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("interrupted") = py::none(),
      (std::string("(vertices, faces) of CH(C) \\ C for a closed outward mesh (triangles in R^3) or "
                   "counter-clockwise polygons (edges in R^2); empty arrays when C is convex. Raises BooleanError "
                   "naming what CGAL refused.") +
       kBooleanInterrupterDoc)
          .c_str());
  m.def(
      "intersect_solids",
      [](PointsRef VA, SimplicesRef FA, PointsRef VB, SimplicesRef FB, const py::object& interrupted) {
        const Interrupter interrupter = interrupter_from(py::none(), interrupted);
        Solid s = without_gil([&] { return intersect_solids(VA, FA, VB, FB, interrupter); });
        return py::make_tuple(std::move(s.vertices), std::move(s.faces));
      },
      py::arg("vertices_a"), py::arg("faces_a"), py::arg("vertices_b"), py::arg("faces_b"), py::kw_only(),
      py::arg("interrupted") = py::none(),
      (std::string("(vertices, faces) of A ∩ B for closed solids (both 3D meshes or both 2D polygons); raises "
                   "BooleanError.") +
       kBooleanInterrupterDoc)
          .c_str());
  m.def(
      "subtract_solid",
      [](PointsRef V, SimplicesRef F, PointsRef VH, SimplicesRef FH, const py::object& interrupted) {
        const Interrupter interrupter = interrupter_from(py::none(), interrupted);
        Subtraction r = without_gil([&] { return subtract_solid(V, F, VH, FH, interrupter); });
        return py::make_tuple(std::move(r.solid.vertices), std::move(r.solid.faces), r.unchanged);
      },
      py::arg("vertices"), py::arg("faces"), py::arg("hole_vertices"), py::arg("hole_faces"), py::kw_only(),
      py::arg("interrupted") = py::none(),
      (std::string("(vertices, faces, unchanged) of frame \\ H; `unchanged` is True when H cannot touch the "
                   "frame (the arrays are then a copy of the frame's). Raises BooleanError.") +
       kBooleanInterrupterDoc)
          .c_str());
  m.def(
      "points_inside_solid",
      [](PointsRef V, SimplicesRef F, PointsRef P) {
        return without_gil([&] { return points_inside_solid(V, F, P); });
      },
      py::arg("vertices"), py::arg("faces"), py::arg("points"),
      "Whether each point (#P, 3) lies inside (or on) the closed outward triangle mesh; cavities and "
      "tunnels are outside.");
  m.def("solid_measure", [](PointsRef V, SimplicesRef F) { return solid_measure(V, F); }, py::arg("vertices"),
        py::arg("faces"), "Volume (3D) or area (2D) enclosed by a closed outward boundary.");
}

}  // namespace animanifold::bindings
