#include "animanifold/subdivide.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

namespace {

// subdivide_manifold()'s result with the manifold shared, so that Python
// wraps it without copying it.
struct SubdividedManifold {
  std::shared_ptr<Complex> manifold;
  SimplexMatrix vertex_parents;
  IndexVector simplex_parent;
  Eigen::VectorXd keyframe_times;
};

// The options the frame bindings share, from their keyword arguments.
FrameSubdivisionOptions frame_options(int levels, double crease_angle, bool limit, FrameScheme scheme) {
  FrameSubdivisionOptions options;
  options.levels = levels;
  options.scheme = scheme;
  options.crease_angle_degrees = crease_angle;
  options.limit = limit;
  return options;
}

void bind_frame_subdivision(py::module_& m) {
  py::class_<FrameSubdivision>(m, "FrameSubdivision", "A frame (or polyline) refined by subdivide_frame/_polyline.")
      .def_property_readonly("vertices", copy_of(&FrameSubdivision::vertices), "#V' by 3 refined points.")
      .def_property_readonly("faces", copy_of(&FrameSubdivision::faces),
                             "#F' by 3 (Loop), 4 (Catmull-Clark) or 2 (segments), oriented like the input.")
      .def_property_readonly("normals", copy_of(&FrameSubdivision::normals),
                             "#V' by 3 unit area-weighted normals of the refined mesh.")
      .def_property_readonly("vertex_attributes", copy_of(&FrameSubdivision::vertex_attributes),
                             "Per-vertex tables refined with the same stencils as the points.")
      .def_property_readonly("face_attributes", copy_of(&FrameSubdivision::face_attributes),
                             "Per-face tables inherited from the input face.")
      .def_property_readonly("face_parent", copy_of(&FrameSubdivision::face_parent),
                             "#F': the input face each face descends from.")
      .def_readonly("crease_count", &FrameSubdivision::crease_count,
                    "Input edges made sharp (corners for polylines).");
}

}  // namespace

void bind_subdivide(py::module_& m) {
  bind_frame_subdivision(m);
  bind_named_enum(m, "FrameScheme", "frame subdivision scheme", kFrameSchemeNames,
                  "Frame subdivision: loop (triangles), catmull_clark (triangles or quads), bspline (polylines).");
  bind_named_enum(m, "ManifoldScheme", "manifold subdivision scheme", kManifoldSchemeNames,
                  "Tetrahedral subdivision: schaefer (split and average: smooth) or linear (split only).");
  // Array properties return copies: callers own what they are given.
  py::class_<SubdividedManifold>(m, "SubdividedManifold", "A subdivided manifold and its maps to the input.")
      .def_readonly("manifold", &SubdividedManifold::manifold, "The subdivided Complex.")
      .def_property_readonly("vertex_parents", copy_of(&SubdividedManifold::vertex_parents),
                             "#V' by 2: the input vertices each new vertex lies between (equal for kept ones).")
      .def_property_readonly("simplex_parent", copy_of(&SubdividedManifold::simplex_parent),
                             "#S': the input simplex each output simplex lies in.")
      .def_property_readonly("keyframe_times", copy_of(&SubdividedManifold::keyframe_times),
                             "Times kept exact by the subdivision.");
  m.def("subdivide_manifold",
        [](const Complex& c, int levels, ManifoldScheme scheme, bool keep_keyframe_times,
           std::vector<double> keyframe_times, const py::object& progress, const py::object& interrupted) {
          ManifoldSubdivisionOptions options;
          options.levels = levels;
          options.scheme = scheme;
          options.keep_keyframe_times = keep_keyframe_times;
          options.keyframe_times = std::move(keyframe_times);
          const Interrupter interrupter = interrupter_from(progress, interrupted);
          ManifoldSubdivision result = without_gil([&] { return subdivide_manifold(c, options, interrupter); });
          return SubdividedManifold{std::make_shared<Complex>(std::move(result.manifold)),
                                    std::move(result.vertex_parents), std::move(result.simplex_parent),
                                    std::move(result.keyframe_times)};
        },
        py::arg("manifold"), py::arg("levels") = 1, py::arg("scheme") = ManifoldScheme::Schaefer,
        py::arg("keep_keyframe_times") = false, py::arg("keyframe_times") = std::vector<double>{}, py::kw_only(),
        py::arg("progress") = py::none(), py::arg("interrupted") = py::none(),
        (std::string("Schaefer et al. 2004 subdivision of a tet (or triangle) manifold: a SubdividedManifold; raises "
                     "InputError for an unknown scheme or bad levels, MemoryLimitError when the result would not fit the "
                     "memory limit.") +
         kInterrupterDoc)
            .c_str());

  m.def("subdivide_frame",
        [](PointsRef V, SimplicesRef F, int levels, FrameScheme scheme, double crease_angle,
           std::optional<SimplexMatrix> crease_edges, bool limit, VertexAttributes vertex_attributes,
           SimplexAttributes face_attributes, const py::object& progress, const py::object& interrupted) {
          FrameSubdivisionOptions options = frame_options(levels, crease_angle, limit, scheme);
          if (crease_edges) options.crease_edges = std::move(*crease_edges);
          const Interrupter interrupter = interrupter_from(progress, interrupted);
          return without_gil(
              [&] { return subdivide_frame(V, F, options, vertex_attributes, face_attributes, interrupter); });
        },
        py::arg("vertices"), py::arg("faces"), py::arg("levels") = 1, py::arg("scheme") = FrameScheme::Loop,
        py::arg("crease_angle") = 30.0, py::arg("crease_edges") = py::none(), py::arg("limit") = true,
        py::arg("vertex_attributes") = VertexAttributes{}, py::arg("face_attributes") = SimplexAttributes{},
        py::kw_only(), py::arg("progress") = py::none(), py::arg("interrupted") = py::none(),
        (std::string("OpenSubdiv refinement of a triangle/quad mesh with creases at sharp edges: a FrameSubdivision; "
                     "raises InputError for a bad mesh or scheme, MemoryLimitError when the result would not fit the "
                     "memory limit.") +
         kInterrupterDoc)
            .c_str());

  m.def("subdivide_polyline",
        [](PointsRef V, SimplicesRef E, int levels, double crease_angle, bool limit, VertexAttributes vertex_attributes,
           SimplexAttributes segment_attributes, const py::object& progress, const py::object& interrupted) {
          const FrameSubdivisionOptions options = frame_options(levels, crease_angle, limit, FrameScheme::BSpline);
          const Interrupter interrupter = interrupter_from(progress, interrupted);
          return without_gil(
              [&] { return subdivide_polyline(V, E, options, vertex_attributes, segment_attributes, interrupter); });
        },
        py::arg("vertices"), py::arg("segments"), py::arg("levels") = 1, py::arg("crease_angle") = 30.0,
        py::arg("limit") = true, py::arg("vertex_attributes") = VertexAttributes{},
        py::arg("segment_attributes") = SimplexAttributes{}, py::kw_only(), py::arg("progress") = py::none(),
        py::arg("interrupted") = py::none(),
        (std::string("Cubic B-spline subdivision of polylines with corners at sharp turns (frames of 2D animations): "
                     "a FrameSubdivision.") +
         kInterrupterDoc)
            .c_str());

  m.def("smooth_slice",
        [](const Slice& s, int levels, double crease_angle, bool limit) {
          const FrameSubdivisionOptions options = frame_options(levels, crease_angle, limit, FrameScheme::Loop);
          return without_gil([&] { return std::make_shared<Slice>(smooth_slice(s, options)); });
        },
        py::arg("slice"), py::arg("levels"), py::arg("crease_angle") = 30.0, py::arg("limit") = true,
        "A frame refined with Loop subdivision (OpenSubdiv), or B-spline curves for 2D animations; face_simplex inherited.");
}

}  // namespace animanifold::bindings
