#include "animanifold/delaunay.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

namespace {

py::dict to_dict(const ConformingDelaunay& c) {
  py::dict out;
  out["points"] = c.points;
  out["simplices"] = c.simplices;
  out["constraints"] = c.constraints;
  out["constraint_parent"] = c.constraint_parent;
  out["is_delaunay"] = c.is_delaunay;
  out["non_delaunay_faces"] = c.non_delaunay_faces;
  out["mending_rounds"] = c.mending_rounds;
  out["mended_points"] = c.mended_points;
  return out;
}

}  // namespace

void bind_delaunay(py::module_& m) {
  // (simplices, flat_count, flat_simplices) of a triangulation, computed without the GIL.
  auto triangulation = [](DelaunayTriangulation (*triangulate)(const PointMatrix&)) {
    return [triangulate](PointsRef points) {
      DelaunayTriangulation dt;
      {
        py::gil_scoped_release release;
        dt = triangulate(points);
      }
      return py::make_tuple(dt.simplices, dt.flat_simplices, dt.flat);
    };
  };
  m.def("delaunay", triangulation([](const PointMatrix& p) { return delaunay(p); }), py::arg("points"),
        "(simplices, flat_count, flat_simplices): Delaunay triangulation in any dimension (Qhull).");
  m.def("delaunay_exact", triangulation(&delaunay_exact), py::arg("points"),
        "(simplices, flat_count, flat_simplices): Delaunay triangulation in R^3 or R^4 (CGAL).");
  m.def("conforming_delaunay_3d",
        [](PointsRef points, SimplicesRef faces) {
          ConformingDelaunay c;
          {
            py::gil_scoped_release release;
            c = conforming_delaunay_3d(points, faces, raise_pending_python_signals);
          }
          return to_dict(c);
        },
        py::arg("points"), py::arg("faces"), "Conforming Delaunay tetrahedralization (TetGen -pD).");
  m.def("conforming_delaunay_2d",
        [](PointsRef points, SimplicesRef edges) {
          ConformingDelaunay c;
          {
            py::gil_scoped_release release;
            c = conforming_delaunay_2d(points, edges);
          }
          return to_dict(c);
        },
        py::arg("points"), py::arg("edges"), "Conforming Delaunay triangulation (CGAL).");
  m.def("missing_facets", [](SimplicesRef simplices, SimplicesRef faces) { return missing_facets(simplices, faces); },
        py::arg("simplices"), py::arg("faces"), "Rows of faces that are not faces of any simplex (Theorem 5.2.1).");
}

}  // namespace animanifold::bindings
