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

void bind_delaunay(py::module_& m, py::module_& testing) {
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
  testing.def("delaunay", triangulation([](const PointMatrix& p) { return delaunay(p); }), py::arg("points"),
        "(simplices, flat_count, flat_simplices): Delaunay triangulation of points (#P by d) in any dimension "
        "(Qhull); raises InputError for too few or non-finite points, MeshingError when Qhull fails.");
  testing.def("delaunay_exact", triangulation(&delaunay_exact), py::arg("points"),
        "(simplices, flat_count, flat_simplices): Delaunay triangulation of points (#P by 3 or 4) (CGAL); "
        "raises InputError for bad points, MeshingError when CGAL fails.");
  testing.def("conforming_delaunay_3d",
        [](PointsRef points, SimplicesRef faces) {
          ConformingDelaunay c;
          {
            py::gil_scoped_release release;
            c = conforming_delaunay_3d(points, faces, raise_pending_python_signals);
          }
          return to_dict(c);
        },
        py::arg("points"), py::arg("faces"), "Conforming Delaunay tetrahedralization (TetGen -pD) of points (#P by 3) and constraint triangles "
        "(#F by 3), as a dict of its arrays; raises InputError for bad indices, MeshingError when TetGen fails.");
  testing.def("conforming_delaunay_2d",
        [](PointsRef points, SimplicesRef edges) {
          ConformingDelaunay c;
          {
            py::gil_scoped_release release;
            c = conforming_delaunay_2d(points, edges);
          }
          return to_dict(c);
        },
        py::arg("points"), py::arg("edges"), "Conforming Delaunay triangulation (CGAL) of points (#P by 2) and constraint segments (#E by 2), as a "
        "dict of its arrays; raises InputError for bad indices, MeshingError when CGAL fails.");
  testing.def("missing_facets", [](SimplicesRef simplices, SimplicesRef faces) { return missing_facets(simplices, faces); },
        py::arg("simplices"), py::arg("faces"), "Rows of faces that are not faces of any simplex (Theorem 5.2.1).");
}

}  // namespace animanifold::bindings
