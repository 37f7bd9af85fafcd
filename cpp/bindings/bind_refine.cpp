#include "animanifold/refine.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_refine(py::module_& m) {
  py::enum_<RefineOrder>(m, "RefineOrder", "Order in which split tuples are applied (§6.3).")
      .value("given", RefineOrder::Given)
      .value("degeneracy", RefineOrder::Degeneracy);

  m.def("refine",
        [](PointsRef V, SimplicesRef S, VertexAttributes vertex_attributes, SimplexAttributes simplex_attributes,
           SimplicesRef split_vertices, PointsRef split_barycentric, double epsilon, RefineOrder order) {
          Complex input{V, S, std::move(vertex_attributes), std::move(simplex_attributes)};
          const SimplexMatrix ids = split_vertices;
          const PointMatrix coords = split_barycentric;
          Refinement r;
          {
            py::gil_scoped_release release;
            r = refine(input, ids, coords, RefineOptions{epsilon, order});
          }
          py::dict out;
          out["points"] = py::cast(std::move(r.complex.V));
          out["simplices"] = py::cast(std::move(r.complex.S));
          out["vertex_attributes"] = py::cast(std::move(r.complex.vertex_attributes));
          out["simplex_attributes"] = py::cast(std::move(r.complex.simplex_attributes));
          out["new_vertex_of_split"] = py::cast(std::move(r.new_vertex_of_split));
          out["snapped_vertex_of_split"] = py::cast(std::move(r.snapped_vertex_of_split));
          out["split_of_vertex"] = py::cast(std::move(r.split_of_vertex));
          out["parent_simplex"] = py::cast(std::move(r.parent_simplex));
          out["applied_simplex"] = py::cast(std::move(r.applied_simplex));
          out["applied_barycentric"] = py::cast(std::move(r.applied_barycentric));
          return out;
        },
        py::arg("points"), py::arg("simplices"), py::arg("vertex_attributes"), py::arg("simplex_attributes"),
        py::arg("split_vertices"), py::arg("split_barycentric"), py::arg("epsilon") = 1e-3,
        py::arg("order") = RefineOrder::Degeneracy,
        "Barycentric refinement (chapter 6). split_vertices (T by m, -1 padded) and split_barycentric (T by m) "
        "are the split tuples; returns a dict of the refined arrays and the maps of animanifold/refine.hpp.");
  m.def("edge_length_degeneracy", [](PointsRef V, SimplicesRef S) { return edge_length_degeneracy(V, S); },
        py::arg("points"), py::arg("simplices"),
        "Variance of each simplex's edge lengths over their squared mean (§6.3). #S vector.");
}

}  // namespace animanifold::bindings
