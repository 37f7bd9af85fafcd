#include "animanifold/delaunay.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

namespace {

void bind_conforming_result(py::module_& testing) {
  py::class_<ConformingDelaunay>(testing, "ConformingDelaunay",
                                 "A conforming Delaunay triangulation and its refined constraints (delaunay.hpp).")
      .def_property_readonly("points", copy_of(&ConformingDelaunay::points),
                             "Input points first (same indices), then the Steiner points the mesher added.")
      .def_property_readonly("simplices", copy_of(&ConformingDelaunay::simplices),
                             "The Delaunay triangulation of `points`, positively oriented.")
      .def_property_readonly("constraints", copy_of(&ConformingDelaunay::constraints),
                             "The refined constraints, each oriented like the input constraint it lies in.")
      .def_property_readonly("constraint_parent", copy_of(&ConformingDelaunay::constraint_parent),
                             "The input constraint each refined one lies in.")
      .def_readonly("is_delaunay", &ConformingDelaunay::is_delaunay,
                    "Every refined constraint is a face of the Delaunay triangulation.")
      .def_readonly("non_delaunay_faces", &ConformingDelaunay::non_delaunay_faces,
                    "Refined constraints that are not faces of the triangulation.")
      .def_readonly("mending_rounds", &ConformingDelaunay::mending_rounds,
                    "3D: how many times TetGen ran again after mending.")
      .def_readonly("mended_points", &ConformingDelaunay::mended_points, "3D: points the mending added.");
}

}  // namespace

void bind_delaunay(py::module_& m, py::module_& testing) {
  bind_conforming_result(testing);
  // (simplices, flat_count, flat_simplices) of a triangulation, computed without the GIL.
  auto triangulation = [](DelaunayTriangulation (*triangulate)(const PointMatrix&)) {
    return [triangulate](PointsRef points) {
      DelaunayTriangulation dt = without_gil([&] { return triangulate(points); });
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
          return without_gil([&] { return conforming_delaunay_3d(points, faces, raise_pending_python_signals); });
        },
        py::arg("points"), py::arg("faces"), "Conforming Delaunay tetrahedralization (TetGen -pD) of points (#P by 3) and constraint triangles "
        "(#F by 3): a ConformingDelaunay; raises InputError for bad indices, MeshingError when TetGen fails or "
        "its mending cascades.");
  testing.def("conforming_delaunay_2d",
        [](PointsRef points, SimplicesRef edges) {
          return without_gil([&] { return conforming_delaunay_2d(points, edges); });
        },
        py::arg("points"), py::arg("edges"), "Conforming Delaunay triangulation (CGAL) of points (#P by 2) and constraint segments (#E by 2): a "
        "ConformingDelaunay; raises InputError for bad indices, MeshingError when CGAL fails.");
  testing.def("missing_facets", [](SimplicesRef simplices, SimplicesRef faces) { return missing_facets(simplices, faces); },
        py::arg("simplices"), py::arg("faces"), "Rows of faces that are not faces of any simplex (Theorem 5.2.1).");
}

}  // namespace animanifold::bindings
