#include "animanifold/corner_charts.hpp"
#include "animanifold/morph.hpp"
#include "animanifold/morph_validity.hpp"
#include "animanifold/self_intersection.hpp"
#include "animanifold/surface_distance.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

namespace {

py::dict report_dict(const MorphReport& report) {
  py::dict out;
  for_each_entry(report, [&](const char* name, const auto& value) { out[name] = value; });
  return out;
}

void bind_options_and_report(py::module_& m) {
  bind_named_enum(m, "MorphMethod", "morph method", kMorphMethodNames, "How a morph fills the space between its inputs.");
  bind_named_enum(m, "FillTriangulation", "fill triangulation", kFillTriangulationNames, "The seed methods' Delaunay fill.");
  bind_named_enum(m, "Perturbation", "perturbation", kPerturbationNames, "How the seed methods put the inputs in general position.");
  py::class_<MorphOptions>(m, "MorphOptions", "The morph's options (cpp/include/animanifold/morph.hpp documents each).")
      .def(py::init<>(), "The default options.")
      .def_readwrite("t0", &MorphOptions::t0)
      .def_readwrite("t1", &MorphOptions::t1)
      .def_readwrite("method", &MorphOptions::method)
      .def_readwrite("max_push", &MorphOptions::max_push)
      .def_readwrite("fill", &MorphOptions::fill)
      .def_readwrite("perturbation", &MorphOptions::perturbation)
      .def_readwrite("fan_flat_polygons", &MorphOptions::fan_flat_polygons)
      .def_readwrite("field_layers", &MorphOptions::field_layers)
      .def_readwrite("field_resolution", &MorphOptions::field_resolution)
      .def_readwrite("hold_stage", &MorphOptions::hold_stage)
      .def_readwrite("hold_seconds", &MorphOptions::hold_seconds)
      .def_readwrite("mesher_time_limit", &MorphOptions::mesher_time_limit);
  py::class_<MorphReport>(m, "MorphReport", "What the morph's checks found and what each stage cost (morph.hpp).")
      .def("to_dict", &report_dict, "The report as a dict of plain values (what the cache stores).")
      .def("__getitem__", [](const MorphReport& r, const std::string& key) -> py::object {
        const py::dict entries = report_dict(r);
        if (!entries.contains(key)) throw py::key_error(key);
        return entries[py::str(key)];  // a new reference, before `entries` goes
      }, py::arg("key"), "One entry of the report by name; raises KeyError for an unknown name.");
}

}  // namespace

void bind_morph(py::module_& m, py::module_& testing) {
  bind_options_and_report(m);
  m.def(
      "morph",
      [](PointsRef VS, SimplicesRef FS, PointsRef VT, SimplicesRef FT, py::object options, py::object progress,
         py::object interrupted, py::kwargs fields) {
        // The options given, with any of their fields overridden by keyword.
        py::object chosen = py::cast(options.is_none() ? MorphOptions{} : options.cast<MorphOptions>());
        for (const auto& [name, value] : fields) {
          if (!py::hasattr(chosen, name)) throw py::type_error("morph() has no option " + py::str(name).cast<std::string>());
          // An enum given by name goes through its type's constructor, whose error names the choices.
          const py::object current = chosen.attr(name);
          const bool named_enum = py::isinstance<py::str>(value) && !py::isinstance<py::str>(current);
          chosen.attr(name) = named_enum ? current.get_type()(value) : py::reinterpret_borrow<py::object>(value);
        }
        MorphOptions o = chosen.cast<MorphOptions>();
        o.interrupter = interrupter_from(progress, interrupted);
        Morph result = without_gil([&] { return morph(VS, FS, VT, FT, o); });
        return py::make_tuple(std::make_shared<Complex>(std::move(result.manifold)), std::move(result.report));
      },
      py::arg("source_points"), py::arg("source_faces"), py::arg("target_points"), py::arg("target_faces"),
      py::arg("options") = py::none(), py::arg("progress") = py::none(), py::arg("interrupted") = py::none(),
      "Morph between two closed shapes: (manifold Complex, MorphReport). `options` (a MorphOptions; fields may "
      "also be given by keyword, enums by name: method='field'). `progress(stage, fraction)` is called between "
      "stages and `interrupted()` about every 0.1 s while a mesher runs; False from the one, True from the "
      "other, cancels (raises Cancelled). Raises InputError naming a bad input, MeshingError when a mesher fails.");
  testing.def(
      "check_morph_frames",
      [](const Complex& manifold, double t0, double t1, PointsRef VS, SimplicesRef FS, PointsRef VT, SimplicesRef FT) {
        MorphReport report;
        without_gil([&] { check_frames(manifold, t0, t1, VS, FS, VT, FT, report); });
        return report;
      },
      py::arg("manifold"), py::arg("t0"), py::arg("t1"), py::arg("source_points"), py::arg("source_faces"),
      py::arg("target_points"), py::arg("target_faces"),
      "The morph's frame checks (morph_validity.hpp) on a manifold (tets in R^4) that should run from the "
      "source at t0 to the target at t1: a MorphReport with frames_checked, frames_capped, topology_changes, "
      "crossing_frames, bubble_frames, largest_bubble_fraction and noise_frames filled in.");
  m.def("check_morph_input",
        [](const PointMatrix& V, SimplicesRef F, const std::string& name) { check_morph_input(V, F, name); },
        py::arg("vertices"), py::arg("faces"), py::arg("name"),
        py::call_guard<py::gil_scoped_release>(),
        "Raises InputError (a ValueError) naming the shape (`name`) and the face or vertex when morph() would refuse it.");
  m.def(
      "self_intersections",
      [](PointsRef V, SimplicesRef F, std::size_t max_pairs, double tolerance) {
        const PointMatrix v = V;
        const SimplexMatrix f = F;
        return without_gil([&] { return self_intersections(v, f, max_pairs, tolerance); });
      },
      py::arg("vertices"), py::arg("faces"), py::arg("max_pairs") = 1, py::arg("tolerance") = 0.0,
      "Pairs of faces of a closed shape that cross (not along shared edges/corners); max_pairs=0: all. "
      "tolerance > 0: only pairs that pass through each other by more than that (rounding left out).");
  m.def(
      "distances_to_surface",
      [](PointsRef points, PointsRef V, SimplicesRef F) {
        const PointMatrix p = points, v = V;
        const SimplexMatrix f = F;
        return without_gil([&] { return Eigen::VectorXd(distances_to_surface(p, v, f)); });
      },
      py::arg("points"), py::arg("vertices"), py::arg("faces"),
      "Distance from each point to the surface (triangles in R^3, segments in R^2); inf without faces.");
  m.def(
      "closest_points",
      [](PointsRef points, PointsRef V, SimplicesRef F) {
        const PointMatrix p = points, v = V;
        const SimplexMatrix f = F;
        ClosestPoints c = without_gil([&] { return closest_points(p, v, f); });
        return py::make_tuple(Eigen::VectorXd(std::move(c.distance)), IndexVector(std::move(c.face)),
                              PointMatrix(std::move(c.barycentric)));
      },
      py::arg("points"), py::arg("vertices"), py::arg("faces"),
      "(distance, face, barycentric) of the closest point on a closed triangle mesh to each point (#P, 3): "
      "its unsigned distance, the face it lies on, and its barycentric coordinates in that face's corners.");
  m.def(
      "vertex_face_pairs",
      [](SimplicesRef simplices, IndicesRef face, Index vertices) {
        const SimplexMatrix s = simplices;
        const IndexVector f = face;
        VertexFacePairs pairs = without_gil([&] { return vertex_face_pairs(s, f, vertices); });
        return py::make_tuple(std::move(pairs.vertex), std::move(pairs.face), std::move(pairs.corner_pair));
      },
      py::arg("simplices"), py::arg("face"), py::arg("vertices"),
      "(vertex, face, corner_pair): the distinct (vertex, face) pairs the simplices' corners use, each corner "
      "taking its simplex's face, ascending by vertex then face, and each corner's pair (corner_charts.hpp).");
  m.def(
      "chart_labels",
      [](const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>& owner,
         const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv, const Eigen::VectorXd& tolerance) {
        return without_gil([&] { return chart_labels(owner, uv, tolerance); });
      },
      py::arg("owner"), py::arg("uv"), py::arg("tolerance"),
      "Per item, its chart: items of one owner whose UVs agree to the tolerance, neighbours in the order of "
      "(owner, u, v) and of (owner, v, u), share one; numbered in the order of each chart's first item "
      "(corner_charts.hpp).");
  testing.def("external_skeleton_points",
        [](const PointMatrix& V, SimplicesRef F, double gap) { return external_skeleton_points(V, F, gap); },
        py::arg("points"), py::arg("faces"), py::arg("gap"),
        py::call_guard<py::gil_scoped_release>(),
        "Vertices of the external Voronoi skeleton off the surface, at least gap apart (§8.6.1).");
}

}  // namespace animanifold::bindings
