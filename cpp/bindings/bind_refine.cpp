#include "animanifold/refine.hpp"
#include "bindings.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

void bind_refine(py::module_& m, py::module_& testing) {
  bind_named_enum(m, "RefineOrder", "refine order", kRefineOrderNames, "Order in which split tuples are applied (§6.3).");

  // Properties return copies: callers own (and may write to) what refine() gives them.
  py::class_<Refinement>(m, "Refinement", "A refined complex and the maps of animanifold/refine.hpp.")
      .def_property_readonly("points", [](const Refinement& r) { return r.complex.V; }, "#V' by D, input vertices first.")
      .def_property_readonly("simplices", [](const Refinement& r) { return r.complex.S; }, "#S' by k+1.")
      .def_property_readonly("vertex_attributes", [](const Refinement& r) { return r.complex.vertex_attributes; },
                             "Per-vertex tables (#V' rows), interpolated at new vertices.")
      .def_property_readonly("simplex_attributes", [](const Refinement& r) { return r.complex.simplex_attributes; },
                             "Per-simplex tables (#S' rows), inherited from the parent simplex.")
      .def_property_readonly("new_vertex_of_split", copy_of(&Refinement::new_vertex_of_split),
                             "Vertex made by each split tuple (T), -1 when it snapped or was skipped.")
      .def_property_readonly("snapped_vertex_of_split", copy_of(&Refinement::snapped_vertex_of_split),
                             "Existing vertex each split tuple snapped to (T), -1 otherwise.")
      .def_property_readonly("split_of_vertex", copy_of(&Refinement::split_of_vertex),
                             "Split tuple that made each vertex (#V'), -1 for input vertices.")
      .def_property_readonly("parent_simplex", copy_of(&Refinement::parent_simplex),
                             "Input simplex each output simplex lies in (#S').")
      .def_property_readonly("applied_simplex", copy_of(&Refinement::applied_simplex),
                             "The simplex each applied split was made in (vertex ids, -1 padded).")
      .def_property_readonly("applied_barycentric", copy_of(&Refinement::applied_barycentric),
                             "Barycentric coordinates of each applied split in its simplex.");

  m.def("refine",
        [](PointsRef V, SimplicesRef S, VertexAttributes vertex_attributes, SimplexAttributes simplex_attributes,
           SimplicesRef split_vertices, PointsRef split_barycentric, double epsilon, RefineOrder order) {
          Complex input{V, S, std::move(vertex_attributes), std::move(simplex_attributes)};
          const SimplexMatrix ids = split_vertices;
          const PointMatrix coords = split_barycentric;
          return without_gil([&] { return refine(input, ids, coords, RefineOptions{epsilon, order}); });
        },
        py::arg("points"), py::arg("simplices"), py::arg("vertex_attributes"), py::arg("simplex_attributes"),
        py::arg("split_vertices"), py::arg("split_barycentric"), py::arg("epsilon") = 1e-3,
        py::arg("order") = RefineOrder::Degeneracy,
        "Barycentric refinement (chapter 6). split_vertices (T by m, -1 padded) and split_barycentric (T by m) "
        "are the split tuples; returns a Refinement. "
        "Raises InputError naming a bad split tuple, MemoryLimitError when the result would not fit the memory limit.");
  testing.def("edge_length_degeneracy", [](PointsRef V, SimplicesRef S) { return edge_length_degeneracy(V, S); },
        py::arg("points"), py::arg("simplices"),
        "Variance of each simplex's edge lengths over their squared mean (§6.3). #S vector.");
}

}  // namespace animanifold::bindings
