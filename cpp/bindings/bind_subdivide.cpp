#include "animanifold/subdivide.hpp"
#include "bindings.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

namespace {

py::dict to_dict(FrameSubdivision&& r) {
  py::dict out;
  out["vertices"] = std::move(r.vertices);
  out["faces"] = std::move(r.faces);
  out["normals"] = std::move(r.normals);
  out["vertex_attributes"] = std::move(r.vertex_attributes);
  out["face_attributes"] = std::move(r.face_attributes);
  out["face_parent"] = std::move(r.face_parent);
  out["crease_count"] = r.crease_count;
  return out;
}

// subdivide_manifold()'s result with the manifold shared, so that Python
// wraps it without copying it.
struct SubdividedManifold {
  std::shared_ptr<Complex> manifold;
  SimplexMatrix vertex_parents;
  IndexVector simplex_parent;
  Eigen::VectorXd keyframe_times;
};

}  // namespace

void bind_subdivide(py::module_& m) {
  bind_named_enum(m, "ManifoldScheme", "manifold subdivision scheme", kManifoldSchemeNames,
                  "Tetrahedral subdivision: schaefer (split and average: smooth) or linear (split only).");
  // Array properties return copies: callers own what they are given.
  py::class_<SubdividedManifold>(m, "SubdividedManifold", "A subdivided manifold and its maps to the input.")
      .def_readonly("manifold", &SubdividedManifold::manifold, "The subdivided Complex.")
      .def_property_readonly("vertex_parents", [](const SubdividedManifold& s) { return s.vertex_parents; },
                             "#V' by 2: the input vertices each new vertex lies between (equal for kept ones).")
      .def_property_readonly("simplex_parent", [](const SubdividedManifold& s) { return s.simplex_parent; },
                             "#S': the input simplex each output simplex lies in.")
      .def_property_readonly("keyframe_times", [](const SubdividedManifold& s) { return s.keyframe_times; },
                             "Times kept exact by the subdivision.");
  m.def("subdivide_manifold",
        [](const Complex& c, int levels, ManifoldScheme scheme, bool keep_keyframe_times,
           std::vector<double> keyframe_times) {
          ManifoldSubdivisionOptions options;
          options.levels = levels;
          options.scheme = scheme;
          options.keep_keyframe_times = keep_keyframe_times;
          options.keyframe_times = std::move(keyframe_times);
          ManifoldSubdivision result;
          {
            py::gil_scoped_release release;
            result = subdivide_manifold(c, options);
          }
          return SubdividedManifold{std::make_shared<Complex>(std::move(result.manifold)),
                                    std::move(result.vertex_parents), std::move(result.simplex_parent),
                                    std::move(result.keyframe_times)};
        },
        py::arg("manifold"), py::arg("levels") = 1, py::arg("scheme") = ManifoldScheme::Schaefer,
        py::arg("keep_keyframe_times") = false, py::arg("keyframe_times") = std::vector<double>{},
        "Schaefer et al. 2004 subdivision of a tet (or triangle) manifold: a SubdividedManifold; raises "
        "InputError for an unknown scheme or bad levels.");

  m.def("subdivide_frame",
        [](PointsRef V, SimplicesRef F, int levels, const std::string& scheme, double crease_angle,
           std::optional<SimplexMatrix> crease_edges, bool limit, VertexAttributes vertex_attributes,
           SimplexAttributes face_attributes) {
          FrameSubdivisionOptions options;
          options.levels = levels;
          options.scheme = parse_frame_scheme(scheme);
          options.crease_angle_degrees = crease_angle;
          if (crease_edges) options.crease_edges = std::move(*crease_edges);
          options.limit = limit;
          FrameSubdivision r;
          {
            py::gil_scoped_release release;
            r = subdivide_frame(V, F, options, vertex_attributes, face_attributes);
          }
          return to_dict(std::move(r));
        },
        py::arg("vertices"), py::arg("faces"), py::arg("levels") = 1, py::arg("scheme") = "loop",
        py::arg("crease_angle") = 30.0, py::arg("crease_edges") = py::none(), py::arg("limit") = true,
        py::arg("vertex_attributes") = VertexAttributes{}, py::arg("face_attributes") = SimplexAttributes{},
        "OpenSubdiv refinement of a triangle/quad mesh with creases at sharp edges: dict of arrays (vertices, faces, "
        "normals, vertex_attributes, face_attributes, face_parent, crease_count); raises InputError for a bad mesh or scheme.");

  m.def("subdivide_polyline",
        [](PointsRef V, SimplicesRef E, int levels, double crease_angle, bool limit, VertexAttributes vertex_attributes,
           SimplexAttributes segment_attributes) {
          FrameSubdivisionOptions options;
          options.levels = levels;
          options.crease_angle_degrees = crease_angle;
          options.limit = limit;
          FrameSubdivision r;
          {
            py::gil_scoped_release release;
            r = subdivide_polyline(V, E, options, vertex_attributes, segment_attributes);
          }
          return to_dict(std::move(r));
        },
        py::arg("vertices"), py::arg("segments"), py::arg("levels") = 1, py::arg("crease_angle") = 30.0,
        py::arg("limit") = true, py::arg("vertex_attributes") = VertexAttributes{},
        py::arg("segment_attributes") = SimplexAttributes{},
        "Cubic B-spline subdivision of polylines with corners at sharp turns (frames of 2D animations).");

  m.def("smooth_slice",
        [](const Slice& s, int levels, double crease_angle, bool limit) {
          FrameSubdivisionOptions options;
          options.levels = levels;
          options.crease_angle_degrees = crease_angle;
          options.limit = limit;
          py::gil_scoped_release release;
          return std::make_shared<Slice>(smooth_slice(s, options));
        },
        py::arg("slice"), py::arg("levels"), py::arg("crease_angle") = 30.0, py::arg("limit") = true,
        "A frame refined with Loop subdivision (OpenSubdiv), or B-spline curves for 2D animations; face_simplex inherited.");
}

}  // namespace animanifold::bindings
