#include "animanifold/morph.hpp"
#include "animanifold/morph_skeleton.hpp"
#include "animanifold/self_intersection.hpp"
#include "animanifold/surface_distance.hpp"
#include "bindings.hpp"

namespace animanifold::bindings {

void bind_morph(py::module_& m) {
  m.def(
      "morph",
      [](PointsRef VS, SimplicesRef FS, PointsRef VT, SimplicesRef FT, double t0, double t1, const std::string& method,
         py::object progress, double max_push, const std::string& fill, const std::string& perturbation,
         py::object interrupted, bool fan_flat_polygons, int field_layers, double field_resolution,
         const std::string& hold_stage, double hold_seconds) {
        MorphOptions options;
        options.t0 = t0;
        options.t1 = t1;
        options.method = method;
        options.max_push = max_push;
        options.fill = fill;
        options.perturbation = perturbation;
        options.fan_flat_polygons = fan_flat_polygons;
        options.field_layers = field_layers;
        options.field_resolution = field_resolution;
        options.hold_stage = hold_stage;
        options.hold_seconds = hold_seconds;
        if (!progress.is_none())
          options.progress = [progress](const std::string& stage, double fraction) {
            py::gil_scoped_acquire acquire;
            return progress(stage, fraction).cast<bool>();
          };
        // Ctrl-C, and the caller's own check (a cancel button: the morph may
        // run in a worker thread, where Python's signal handlers never run).
        options.interrupted = [interrupted] {
          raise_pending_python_signals();
          if (interrupted.is_none()) return false;
          py::gil_scoped_acquire acquire;
          return interrupted().cast<bool>();
        };
        Morph result;
        {
          py::gil_scoped_release release;
          result = morph(VS, FS, VT, FT, options);
        }
        const MorphReport& r = result.report;
        py::dict report;
        report["missing_source_faces"] = r.missing_source_faces;
        report["missing_target_faces"] = r.missing_target_faces;
        report["source_conforming"] = r.source_conforming;
        report["target_conforming"] = r.target_conforming;
        report["flat_fill_simplices"] = r.flat_fill_simplices;
        report["peeled_hull_slivers"] = r.peeled_hull_slivers;
        report["exact_convex_fill"] = r.exact_convex_fill;
        report["perturbation"] = r.perturbation;
        report["unnudged_steiner_points"] = r.unnudged_steiner_points;
        report["fill_simplices"] = r.fill_simplices;
        report["stripped_simplices"] = r.stripped_simplices;
        report["simplices"] = r.simplices;
        report["shared_stripped_simplices"] = r.shared_stripped_simplices;
        report["inputs_coincide"] = r.inputs_coincide;
        report["source_skeleton_points"] = r.source_skeleton_points;
        report["target_skeleton_points"] = r.target_skeleton_points;
        report["source_cap_points"] = r.source_cap_points;
        report["target_cap_points"] = r.target_cap_points;
        report["source_fanned_polygons"] = r.source_fanned_polygons;
        report["target_fanned_polygons"] = r.target_fanned_polygons;
        report["source_free_vertices"] = r.source_free_vertices;
        report["target_free_vertices"] = r.target_free_vertices;
        report["split_faces"] = r.split_faces;
        report["refinement_points"] = r.refinement_points;
        report["peeled_slivers"] = r.peeled_slivers;
        report["source_push"] = r.source_push;
        report["target_push"] = r.target_push;
        report["levelled_vertices"] = r.levelled_vertices;
        report["sealed_vertices"] = r.sealed_vertices;
        report["min_volume"] = r.min_volume;
        report["min_relative_volume"] = r.min_relative_volume;
        report["inverted_simplices"] = r.inverted_simplices;
        report["degenerate_simplices"] = r.degenerate_simplices;
        report["source_distance"] = r.source_distance;
        report["target_distance"] = r.target_distance;
        report["ends_reproduced"] = r.ends_reproduced;
        report["source_steiner_points"] = r.source_steiner_points;
        report["target_steiner_points"] = r.target_steiner_points;
        report["field_layers"] = r.field_layers;
        report["lattice_spacing"] = r.lattice_spacing;
        report["frames_checked"] = r.frames_checked;
        report["frames_capped"] = r.frames_capped;
        report["topology_changes"] = r.topology_changes;
        report["crossing_frames"] = r.crossing_frames;
        report["bubble_frames"] = r.bubble_frames;
        report["largest_bubble_fraction"] = r.largest_bubble_fraction;
        report["noise_frames"] = r.noise_frames;
        report["stage_seconds"] = r.stage_seconds;
        return py::make_tuple(std::make_shared<Complex>(std::move(result.manifold)), report);
      },
      py::arg("source_points"), py::arg("source_faces"), py::arg("target_points"), py::arg("target_faces"),
      py::arg("t0") = 0.0, py::arg("t1") = 1.0, py::arg("method") = "skeleton", py::arg("progress") = py::none(),
      py::arg("max_push") = MorphOptions{}.max_push, py::arg("fill") = MorphOptions{}.fill,
      py::arg("perturbation") = MorphOptions{}.perturbation, py::arg("interrupted") = py::none(),
      py::arg("fan_flat_polygons") = MorphOptions{}.fan_flat_polygons,
      py::arg("field_layers") = MorphOptions{}.field_layers, py::arg("field_resolution") = MorphOptions{}.field_resolution,
      py::arg("hold_stage") = "", py::arg("hold_seconds") = 0.0,
      "Morph between two closed shapes: (manifold Complex, validity report dict). `progress(stage, fraction)` "
      "is called between stages and `interrupted()` about every 0.1 s while a mesher runs; False from the one, "
      "True from the other, cancels (raises Cancelled).");
  py::register_exception<Cancelled>(m, "Cancelled");
  m.def(
      "self_intersections",
      [](PointsRef V, SimplicesRef F, std::size_t max_pairs, double tolerance) {
        const PointMatrix v = V;
        const SimplexMatrix f = F;
        py::gil_scoped_release release;
        return self_intersections(v, f, max_pairs, tolerance);
      },
      py::arg("vertices"), py::arg("faces"), py::arg("max_pairs") = 1, py::arg("tolerance") = 0.0,
      "Pairs of faces of a closed shape that cross (not along shared edges/corners); max_pairs=0: all. "
      "tolerance > 0: only pairs that pass through each other by more than that (rounding left out).");
  m.def(
      "distances_to_surface",
      [](PointsRef points, PointsRef V, SimplicesRef F) {
        const PointMatrix p = points, v = V;
        const SimplexMatrix f = F;
        py::gil_scoped_release release;
        return Eigen::VectorXd(distances_to_surface(p, v, f));
      },
      py::arg("points"), py::arg("vertices"), py::arg("faces"),
      "Distance from each point to the surface (triangles in R^3, segments in R^2); inf without faces.");
  m.def("external_skeleton_points", &external_skeleton_points, py::arg("points"), py::arg("faces"), py::arg("gap"),
        py::call_guard<py::gil_scoped_release>(),
        "Vertices of the external Voronoi skeleton off the surface, at least gap apart (§8.6.1).");
}

}  // namespace animanifold::bindings
