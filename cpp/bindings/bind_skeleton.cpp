#include "animanifold/skeleton.hpp"
#include "bindings.hpp"
#include "interrupter.hpp"
#include "named_enum.hpp"

namespace animanifold::bindings {

namespace {

// The results of the separability checks and repairs (skeleton.hpp).
void bind_separability_results(py::module_& m) {
  py::class_<DihedralReport>(m, "DihedralReport", "The mesh's surface angles against a limit (dihedral_test).")
      .def_readonly("limit", &DihedralReport::limit, "The limit tested against (radians).")
      .def_readonly("sharpest", &DihedralReport::sharpest, "The smallest surface angle found (radians).")
      .def_readonly("passes", &DihedralReport::passes, "No surface angle is sharper than the limit.")
      .def_property_readonly("sharp", copy_of(&DihedralReport::sharp),
                             "Where: the shared edge (2 vertices) in 3D, the corner vertex (1 column) in 2D.")
      .def_property_readonly("angles", copy_of(&DihedralReport::angles), "The surface angle at each row of `sharp`.");
  py::class_<SeparabilityResult>(m, "SeparabilityResult", "A mesh made Voronoi-separable (make_voronoi_separable).")
      .def_property_readonly("vertices", copy_of(&SeparabilityResult::vertices),
                             "The refined mesh: input vertices first, then split points.")
      .def_property_readonly("faces", copy_of(&SeparabilityResult::faces), "Conforming and oriented like the input.")
      .def_readonly("separable", &SeparabilityResult::separable, "No encroachment is left.")
      .def_readonly("iterations", &SeparabilityResult::iterations, "Splitting rounds applied (0: it was separable).")
      .def_readonly("splits", &SeparabilityResult::splits, "Vertices inserted.")
      .def_readonly("remaining", &SeparabilityResult::remaining, "Encroached simplices left when the cap was hit.");
}

}  // namespace

// The skeleton itself.
static void bind_voronoi_skeleton(py::module_& m) {
  py::class_<VoronoiSkeleton, std::shared_ptr<VoronoiSkeleton>>(m, "VoronoiSkeleton",
                                                                 "Internal/external Voronoi skeleton (chapter 7).")
      .def_readonly("vertices", &VoronoiSkeleton::vertices)
      .def_readonly("faces", &VoronoiSkeleton::faces)
      .def_readonly("side", &VoronoiSkeleton::side)
      .def_readonly("sites", &VoronoiSkeleton::sites)
      .def_readonly("polygon", &VoronoiSkeleton::polygon)
      .def_readonly("on_mesh", &VoronoiSkeleton::on_mesh)
      .def_readonly("refined_vertices", &VoronoiSkeleton::refined_vertices)
      .def_readonly("refined_faces", &VoronoiSkeleton::refined_faces)
      .def_readonly("separable", &VoronoiSkeleton::separable)
      .def_readonly("iterations", &VoronoiSkeleton::iterations)
      .def_readonly("splits", &VoronoiSkeleton::splits)
      .def_readonly("dihedral", &VoronoiSkeleton::dihedral)
      .def_readonly("attachment", &VoronoiSkeleton::attachment)
      .def_readonly("bisectors", &VoronoiSkeleton::bisectors)
      .def_readonly("discarded", &VoronoiSkeleton::discarded)
      .def_readonly("discarded_nonlocal", &VoronoiSkeleton::discarded_nonlocal)
      .def_readonly("discarded_far", &VoronoiSkeleton::discarded_far)
      .def_readonly("seconds_separability", &VoronoiSkeleton::seconds_separability)
      .def_readonly("seconds_extraction", &VoronoiSkeleton::seconds_extraction);

  m.def("voronoi_skeleton",
        [](PointsRef V, SimplicesRef F, SkeletonSide side, int max_iterations, WrapShape wrap, int wrap_density,
           double wrap_margin, double dihedral_limit, bool attach, int neighbourhood, double in_plane_angle,
           const py::object& progress, const py::object& interrupted) {
          SkeletonOptions o;
          o.internal = side != SkeletonSide::External;
          o.external = side != SkeletonSide::Internal;
          o.max_iterations = max_iterations;
          o.wrap = wrap;
          o.wrap_density = wrap_density;
          o.wrap_margin = wrap_margin;
          o.dihedral_limit = dihedral_limit;
          o.attach = attach;
          o.rule = {neighbourhood, in_plane_angle};
          const PointMatrix v = V;
          const SimplexMatrix f = F;
          const Interrupter interrupter = interrupter_from(progress, interrupted);
          return without_gil([&] { return std::make_shared<VoronoiSkeleton>(voronoi_skeleton(v, f, o, interrupter)); });
        },
        py::arg("vertices"), py::arg("faces"), py::arg("side") = SkeletonSide::Both,
        py::arg("max_iterations") = 4, py::arg("wrap") = WrapShape::Box, py::arg("wrap_density") = 4,
        py::arg("wrap_margin") = 1.0, py::arg("dihedral_limit") = M_PI / 4, py::arg("attach") = false, py::arg("neighbourhood") = 2,
        py::arg("in_plane_angle") = 0.3, py::kw_only(), py::arg("progress") = py::none(),
        py::arg("interrupted") = py::none(),
        (std::string("The `side` Voronoi skeleton(s) of a closed triangle mesh (vertices #V by 3, faces #F by 3), "
                     "made Voronoi-separable first; raises InputError for a bad mesh or wrap name, MeshingError when "
                     "Qhull fails.") +
         kInterrupterDoc)
            .c_str());

}

// Making an input separable, and the checks and repairs around it.
static void bind_separability(py::module_& m) {
  m.def("make_voronoi_separable",
        [](PointsRef V, SimplicesRef F, int max_iterations, int neighbourhood, double in_plane_angle) {
          const PointMatrix v = V;
          const SimplexMatrix f = F;
          return without_gil(
              [&] { return make_voronoi_separable(v, f, max_iterations, {neighbourhood, in_plane_angle}); });
        },
        py::arg("vertices"), py::arg("faces"), py::arg("max_iterations") = 4, py::arg("neighbourhood") = 2,
        py::arg("in_plane_angle") = 0.3,
        "Splits encroached faces until the mesh is Voronoi-separable (§7.2): a SeparabilityResult.");

  m.def("encroachments",
        [](PointsRef V, SimplicesRef F, int neighbourhood, double in_plane_angle) {
          const PointMatrix v = V;
          const SimplexMatrix f = F;
          const std::vector<Encroachment> found =
              without_gil([&] { return encroachments(v, f, {neighbourhood, in_plane_angle}); });
          SimplexMatrix rows(static_cast<Index>(found.size()), 5);
          Eigen::VectorXd distance(static_cast<Index>(found.size()));
          for (size_t i = 0; i < found.size(); ++i) {
            const auto& e = found[i];
            rows.row(static_cast<Index>(i)) << e.vertex, e.a, e.b, e.c, e.type;
            distance[static_cast<Index>(i)] = e.distance;
          }
          return py::make_tuple(rows, distance);
        },
        py::arg("vertices"), py::arg("faces"), py::arg("neighbourhood") = 2, py::arg("in_plane_angle") = 0.3,
        "(rows, distance): rows (vertex, a, b, c or -1, type 2/3/4) per encroached simplex and its closest encroacher.");

  m.def("dihedral_test",
        [](PointsRef V, SimplicesRef F, double limit) {
          const PointMatrix v = V;
          const SimplexMatrix f = F;
          return without_gil([&] { return dihedral_test(v, f, limit); });
        },
        py::arg("vertices"), py::arg("faces"), py::arg("limit") = M_PI / 4,
        "Dihedral angles of the mesh's edges against `limit` (radians): a DihedralReport.");

  m.def("wrap",
        [](PointsRef V, SimplicesRef F, WrapShape shape, int density, double margin) {
          const PointMatrix v = V;
          const SimplexMatrix f = F;
          WrapResult r = without_gil([&] { return wrap(v, f, shape, density, margin); });
          return py::make_tuple(r.vertices, r.faces, r.input_vertices, r.input_faces);
        },
        py::arg("vertices"), py::arg("faces"), py::arg("shape") = WrapShape::Box, py::arg("density") = 4,
        py::arg("margin") = 1.0,
        "(vertices, faces, input_vertices, input_faces): the mesh inside a WrapShape for "
        "the external skeleton; raises InputError for an unknown shape.");

  m.def("faces_intersecting_mesh",
        [](PointsRef QV, SimplicesRef QF, PointsRef V, SimplicesRef F) {
          const PointMatrix qv = QV, v = V;
          const SimplexMatrix qf = QF, f = F;
          std::vector<bool> hit = without_gil([&] { return faces_intersecting_mesh(qv, qf, v, f); });
          Eigen::Matrix<bool, Eigen::Dynamic, 1> out(static_cast<Index>(hit.size()));
          for (size_t i = 0; i < hit.size(); ++i) out[static_cast<Index>(i)] = hit[i];
          return out;
        },
        py::arg("faces_vertices"), py::arg("faces"), py::arg("vertices"), py::arg("mesh_faces"),
        "Per face (triangles in R^3, segments in R^2): does it intersect the mesh? CGAL exact predicates.");
}

void bind_skeleton(py::module_& m) {
  // Before the functions whose defaults are their values.
  bind_named_enum(m, "SkeletonSide", "skeleton side", kSkeletonSideNames,
                  "Which Voronoi skeleton: internal (medial), external (concavities and holes) or both.");
  bind_named_enum(m, "WrapShape", "wrap shape", kWrapShapeNames,
                  "The shape around a mesh that bounds every Voronoi cell of the external skeleton (§7.6.4).");
  bind_separability_results(m);
  bind_voronoi_skeleton(m);
  bind_separability(m);
}

}  // namespace animanifold::bindings
