#include "animanifold/complex.hpp"
#include "animanifold/normals.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

using namespace pybind11::literals;

void bind_complex(py::module_& m, py::module_& testing) {
  py::class_<Complex, std::shared_ptr<Complex>>(m, "Complex",
                                                 "Points (#V by D) and oriented simplices (#S by k+1) "
                                                 "with per-vertex float and per-simplex integer attributes.")
      .def(py::init([](PointsRef V, SimplicesRef S, VertexAttributes va, SimplexAttributes sa) {
             auto c = std::make_shared<Complex>();
             c->V = V;
             c->S = S;
             c->vertex_attributes = std::move(va);
             c->simplex_attributes = std::move(sa);
             c->validate();
             return c;
           }),
           py::arg("points"), py::arg("simplices"), py::arg("vertex_attributes") = VertexAttributes{},
           py::arg("simplex_attributes") = SimplexAttributes{},
           "A complex from points (#V by D), simplices (#S by k+1) and attribute tables; raises InputError "
           "naming the simplex or vertex when they do not fit.")
      // Read-only views into the complex's own memory (no copies).
      .def_property_readonly("points", [](const Complex& c) -> const PointMatrix& { return c.V; },
                             py::return_value_policy::reference_internal, "#V by D, read-only view.")
      .def_property_readonly("simplices", [](const Complex& c) -> const SimplexMatrix& { return c.S; },
                             py::return_value_policy::reference_internal, "#S by k+1, read-only view.")
      .def_property_readonly("vertex_attributes", [](py::object self) {
        const Complex& c = self.cast<const Complex&>();
        py::dict out;
        for (const auto& [name, table] : c.vertex_attributes)
          out[py::str(name)] = py::cast(table, py::return_value_policy::reference_internal, self);
        return out;
      }, "Per-vertex float tables by name (#V rows), read-only views.")
      .def_property_readonly("simplex_attributes", [](py::object self) {
        const Complex& c = self.cast<const Complex&>();
        py::dict out;
        for (const auto& [name, table] : c.simplex_attributes)
          out[py::str(name)] = py::cast(table, py::return_value_policy::reference_internal, self);
        return out;
      }, "Per-simplex integer tables by name (#S rows), read-only views.")
      .def("validate", &Complex::validate,
           "Raises InputError naming the first simplex, vertex or attribute that does not fit the complex.");

  testing.def("facets", [](SimplicesRef S) { return facets(S); }, py::arg("simplices"),
        "All facets (#S*k by k-1), facet i of simplex s at row s*k+i, oriented by the rule of §2.4.");
  m.def("boundary_facets", [](SimplicesRef S) { return boundary_facets(S); }, py::arg("simplices"),
        "Facets (#B by k) that belong to one simplex only, oriented outward.");
  py::class_<ManifoldReport>(m, "ManifoldReport", "What check_manifold found: facet counts by kind (complex.hpp).")
      .def_readonly("interior_facets", &ManifoldReport::interior_facets, "Facets shared by exactly two simplices.")
      .def_readonly("boundary_facets", &ManifoldReport::boundary_facets, "Facets of exactly one simplex.")
      .def_readonly("nonmanifold_facets", &ManifoldReport::nonmanifold_facets, "Facets of three or more simplices.")
      .def_readonly("misoriented_facets", &ManifoldReport::misoriented_facets,
                    "Facets shared by two simplices with the same orientation.")
      .def_readonly("degenerate_simplices", &ManifoldReport::degenerate_simplices, "Simplices repeating a vertex.")
      .def_property_readonly("is_oriented_manifold", &ManifoldReport::is_oriented_manifold,
                             "No non-manifold or misoriented facet and no degenerate simplex.")
      .def("to_dict", [](const ManifoldReport& r) {
        return py::dict("interior_facets"_a = r.interior_facets, "boundary_facets"_a = r.boundary_facets,
                        "nonmanifold_facets"_a = r.nonmanifold_facets, "misoriented_facets"_a = r.misoriented_facets,
                        "degenerate_simplices"_a = r.degenerate_simplices,
                        "is_oriented_manifold"_a = r.is_oriented_manifold());
      }, "The counts and is_oriented_manifold as a dict of plain values (for JSON reports).")
      .def("__repr__", [](py::object self) {
        return "ManifoldReport(" + py::str(self.attr("to_dict")()).cast<std::string>() + ")";
      });
  m.def("check_manifold", [](SimplicesRef S) { return check_manifold(S); }, py::arg("simplices"),
        "Facet counts of simplices (#S by k+1): a ManifoldReport.");
  testing.def("signed_volumes", [](PointsRef V, SimplicesRef S) { return signed_volumes(V, S); },
              py::arg("points"), py::arg("simplices"),
              "Signed volume of each n-simplex in R^n (#S vector); negative when inverted.");
  testing.def("simplex_volumes", [](PointsRef V, SimplicesRef S) { return simplex_volumes(V, S); },
              py::arg("points"), py::arg("simplices"), "Unsigned k-volume of each simplex in any R^D (#S vector).");
  testing.def("simplex_normals", [](PointsRef V, SimplicesRef S) { return simplex_normals(V, S); },
              py::arg("points"), py::arg("simplices"),
              "Unit normal of each n-simplex in R^(n+1) (#S by n+1), oriented by the simplex.");
  m.def("vertex_normals", [](PointsRef V, SimplicesRef S) { return vertex_normals(V, S); }, py::arg("points"),
        py::arg("simplices"), "Volume-weighted unit normals (#V by n+1) of a manifold of n-simplices in R^(n+1).");
  m.def("frame_vertex_normals", [](PointsRef V, SimplicesRef F) { return frame_vertex_normals(V, F); },
        py::arg("vertices"), py::arg("faces"), "Area-weighted unit vertex normals of a frame (triangles in R^3, segments in R^2).");
}

}  // namespace animanifold::bindings
