#include "animanifold/hole_space.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_hole_space(py::module_& m) {
  m.def(
      "hole_space",
      [](PointsRef V, SimplicesRef F) {
        Solid s = without_gil([&] { return hole_space(V, F); });
        return py::make_tuple(std::move(s.vertices), std::move(s.faces));
      },
      py::arg("vertices"), py::arg("faces"),
      "(vertices, faces) of CH(C) \\ C for a closed outward mesh (triangles in R^3) or counter-clockwise "
      "polygons (edges in R^2); empty arrays when C is convex. Raises BooleanError naming what CGAL refused.");
  m.def(
      "intersect_solids",
      [](PointsRef VA, SimplicesRef FA, PointsRef VB, SimplicesRef FB) {
        Solid s = without_gil([&] { return intersect_solids(VA, FA, VB, FB); });
        return py::make_tuple(std::move(s.vertices), std::move(s.faces));
      },
      py::arg("vertices_a"), py::arg("faces_a"), py::arg("vertices_b"), py::arg("faces_b"),
      "(vertices, faces) of A ∩ B for closed solids (both 3D meshes or both 2D polygons); raises BooleanError.");
  m.def(
      "subtract_solid",
      [](PointsRef V, SimplicesRef F, PointsRef VH, SimplicesRef FH) {
        Subtraction r = without_gil([&] { return subtract_solid(V, F, VH, FH); });
        return py::make_tuple(std::move(r.solid.vertices), std::move(r.solid.faces), r.unchanged);
      },
      py::arg("vertices"), py::arg("faces"), py::arg("hole_vertices"), py::arg("hole_faces"),
      "(vertices, faces, unchanged) of frame \\ H; `unchanged` is True when H cannot touch the frame "
      "(the arrays are then a copy of the frame's). Raises BooleanError.");
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
