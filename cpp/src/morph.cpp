#include "animanifold/morph.hpp"

#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/flat_polygons.hpp"
#include "animanifold/morph_convex.hpp"
#include "animanifold/morph_layers.hpp"
#include "animanifold/morph_skeleton.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/perturbation.hpp"
#include "animanifold/self_intersection.hpp"
#include "animanifold/shelling.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/surface_distance.hpp"
#include "morph_field.hpp"
#include "morph_stages.hpp"
#include "morph_validity.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <unordered_map>

namespace animanifold {

namespace {

// The time span a morph is solved over, as a fraction of the shapes' size
// (bounding-box diagonal).
constexpr double kSolveSpan = 0.1;

// The frames' checks may take this share of the morph's own time, and no
// more than kValidityCap seconds (morph_validity.hpp).
constexpr double kValidityShare = 0.25;
constexpr double kValidityCap = 60.0;

// The perturbations tried, as fractions of the size (see morph()): the first
// one under which the mesher and the fill conform is used.
constexpr std::array<double, 3> kPerturbations{1e-7, 1e-6, 1e-5};

struct FlatSimplices {
  Index peeled = 0;  // across the planes, on the hull's boundary: left out
  Index inside = 0;  // across the planes, inside the fill
};

// How far restoring the exact coordinates moves a point of the planes, per
// coordinate at most: the perturbation (`scale` of the shapes' `size`, along
// each of the d axes) and the Steiner points' nudge (a tenth of it).
double restored_distance(int d, double scale, double size) {
  return 1.1 * std::sqrt(static_cast<double>(d)) * scale * size;
}

// How much restoring the exact coordinates can change the determinant of a
// simplex of the fill (#corners = D+1 in R^D) whose longest edge is
// `longest`: each point in the planes moves by at most `moved` per
// coordinate (the perturbation and the Steiner points' nudge), which changes
// each of the D rows of the determinant by at most 2·moved and so the
// determinant by at most D·2·moved·longest^(D-1) (Hadamard's bound on each
// changed row), taken twice for safety.
double restore_bound(double longest, int D, double moved) {
  return 2.0 * D * 2.0 * moved * std::pow(longest, D - 1);
}

// The longest edge of the simplex `corners` (`count` rows of P).
double longest_edge(const PointMatrix& P, const Index* corners, int count) {
  double longest = 0;
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b) longest = std::max(longest, (P.row(corners[a]) - P.row(corners[b])).norm());
  return longest;
}

// Peels slivers off the fill's boundary (shelling.hpp): simplices joining
// the two planes (at least two corners in each: one with all but one corner
// in a plane holds a cell of that plane and stays) that are flat, or nearly,
// in the coordinates the fill was built on (Qhull's left-out flat simplices,
// CGAL's fill.slivers), through lateral facets only (the caps at t0 and t1
// stay whole). They lie where a facet of the hull holds points of both
// planes in one hyperplane (a hull edge of a plate with collinear points, a
// flat side both inputs share). Kept slivers that are peeled are taken out
// of fill.simplices; what is left inside is counted: holes for Qhull's flat
// ones (the fill is refused then), cells for CGAL's (kept: proper for its
// exact predicates).
FlatSimplices peel_hull_slivers(DelaunayTriangulation& fill, Index nS) {
  FlatSimplices result;
  const int corners = static_cast<int>(fill.simplices.cols());
  auto in_source = [&](const Index* ids, int count) {
    int n = 0;
    for (int c = 0; c < count; ++c) n += ids[c] < nS;
    return n;
  };
  // One complex: the kept simplices, then Qhull's left-out flat ones.
  const Index kept = fill.simplices.rows();
  SimplexMatrix all(kept + fill.flat.rows(), corners);
  all.topRows(kept) = fill.simplices;
  if (fill.flat.rows()) all.bottomRows(fill.flat.rows()) = fill.flat;
  std::vector<bool> sliver(kept, false);
  for (const Index r : fill.slivers) sliver[r] = true;
  std::vector<Index> candidates;
  Index left_out_across = 0;
  for (Index r = 0; r < all.rows(); ++r) {
    const int source = in_source(all.row(r).data(), corners);
    if (r >= kept) {
      if (source != 0 && source != corners) ++left_out_across, candidates.push_back(r);
      continue;
    }
    if (sliver[r] && source >= 2 && corners - source >= 2) candidates.push_back(r);
  }
  if (candidates.empty()) return result;
  const std::vector<bool> removed = shell_off(all, candidates, [&](const Index* facet) {
    const int source = in_source(facet, corners - 1);
    return source != 0 && source != corners - 1;  // lateral: not a cap facet
  });
  Index removed_kept = 0, removed_left_out = 0;
  for (Index r = 0; r < all.rows(); ++r)
    if (removed[r]) ++(r < kept ? removed_kept : removed_left_out);
  result.peeled = removed_kept + removed_left_out;
  result.inside = left_out_across - removed_left_out;
  if (removed_kept > 0) {
    SimplexMatrix out(kept - removed_kept, corners);
    for (Index r = 0, k = 0; r < kept; ++r)
      if (!removed[r]) out.row(k++) = fill.simplices.row(r);
    fill.simplices = std::move(out);
    fill.slivers.clear();  // row numbers changed; not read after this
  }
  return result;
}

// A closed, consistently oriented, outward shape, or an InputError naming what is wrong.


// Validity 2: the slices at t0 and t1 are the inputs, both ways: every slice
// vertex and face centre on the input, every input vertex and face centre on
// the slice (face centres catch extra faces whose corners all lie on the
// input, such as a triangle across its inside).
void end_distances(const Complex& manifold, const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                   const SimplexMatrix& FT, const MorphOptions& options, double size, MorphReport& report) {
  const int d = static_cast<int>(VS.cols());
  const double diagonal = std::max(size, 1e-300);
  auto with_face_centres = [](const PointMatrix& V, const SimplexMatrix& F) {
    PointMatrix out(V.rows() + F.rows(), V.cols());
    out.topRows(V.rows()) = V;
    for (Index f = 0; f < F.rows(); ++f) {
      Eigen::RowVectorXd centre = Eigen::RowVectorXd::Zero(V.cols());
      for (int c = 0; c < F.cols(); ++c) centre += V.row(F(f, c));
      out.row(V.rows() + f) = centre / static_cast<double>(F.cols());
    }
    return out;
  };
  auto two_sided = [&](const Slice& s, const PointMatrix& V, const SimplexMatrix& F) {
    return std::max(max_distance_to_surface(with_face_centres(s.vertices, s.faces), V, F),
                    max_distance_to_surface(with_face_centres(V, F), s.vertices, s.faces)) / diagonal;
  };
  const Slice start = slice(manifold, d, options.t0), end = slice(manifold, d, options.t1);
  report.source_distance = two_sided(start, VS, FS);
  report.target_distance = two_sided(end, VT, FT);
  report.ends_reproduced = report.source_distance <= 1e-9 && report.target_distance <= 1e-9;
}

// Validity of a manifold extracted as a zero set (the field method): it is a
// closed oriented manifold but for its ends, and no tet is flat (its volume
// relative to its longest edge cubed).
void zero_set_validity(const Complex& manifold, MorphReport& report) {
  const ManifoldReport check = check_manifold(manifold.S);
  report.inverted_simplices = check.misoriented_facets + check.nonmanifold_facets;
  // From the wedge product's length (simplex_normals), not the Gram
  // determinant, whose square loses half the digits of a thin tet.
  const Eigen::VectorXd volume = simplex_normals(manifold.V, manifold.S).rowwise().norm() / 6.0;
  report.min_relative_volume = volume.size() ? std::numeric_limits<double>::infinity() : 0.0;
  report.min_volume = volume.size() ? volume.minCoeff() : 0.0;
  for (Index s = 0; s < manifold.S.rows(); ++s) {
    const double longest = longest_edge(manifold.V, manifold.S.row(s).data(), 4);
    const double relative = longest > 0 ? volume(s) / (longest * longest * longest) : 0.0;
    report.min_relative_volume = std::min(report.min_relative_volume, relative);
    if (relative <= 1e-14) ++report.degenerate_simplices;
  }
}

}  // namespace

void check_morph_input(const PointMatrix& V, const SimplexMatrix& F, const std::string& name) {
  const int d = static_cast<int>(V.cols());
  if (d != 2 && d != 3) fail<InputError>("the ", name, " must be 2D or 3D, got ", d, "D points");
  if (F.cols() != d)
    fail<InputError>("the ", name, " must have ", d == 3 ? "triangles" : "edges", " as faces, got ", F.cols(), " corners");
  if (F.rows() == 0) fail<InputError>("the ", name, " has no faces");
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < d; ++c)
      if (F(f, c) < 0 || F(f, c) >= V.rows())
        fail<InputError>("the ", name, "'s face ", f, " refers to vertex ", F(f, c), ", outside 0..", V.rows() - 1);
  for (Index v = 0; v < V.rows(); ++v)
    for (int c = 0; c < d; ++c)
      if (!std::isfinite(V(v, c))) fail<InputError>("the ", name, "'s vertex ", v, " is not finite");
  double volume = 0.0;
  if (d == 3) {
    const ManifoldReport report = check_manifold(F);
    if (report.boundary_facets > 0)
      fail<InputError>("the ", name, " is open (", report.boundary_facets, " boundary edges): only closed shapes can be morphed");
    if (report.nonmanifold_facets > 0)
      fail<InputError>("the ", name, " is not a manifold (", report.nonmanifold_facets, " edges in more than two faces)");
    if (report.misoriented_facets > 0 || report.degenerate_simplices > 0)
      fail<InputError>("the ", name, " is not consistently oriented (", report.misoriented_facets, " edges)");
    for (Index f = 0; f < F.rows(); ++f)
      volume += Eigen::Vector3d(V.row(F(f, 0))).dot(Eigen::Vector3d(V.row(F(f, 1))).cross(Eigen::Vector3d(V.row(F(f, 2)))));
  } else {
    std::vector<int> starts(V.rows(), 0), ends(V.rows(), 0);
    for (Index f = 0; f < F.rows(); ++f) ++starts[F(f, 0)], ++ends[F(f, 1)];
    for (Index v = 0; v < V.rows(); ++v)
      if (starts[v] != ends[v] || starts[v] > 1)
        fail<InputError>("the ", name, " is not a closed polygon at vertex ", v, " (", starts[v], " edges leave, ", ends[v],
                         " arrive)");
    for (Index f = 0; f < F.rows(); ++f)
      volume += V(F(f, 0), 0) * V(F(f, 1), 1) - V(F(f, 1), 0) * V(F(f, 0), 1);
  }
  if (volume <= 0)
    fail<InputError>("the ", name, " is inside out (its faces point inward): flip its normals");
  const auto crossing = self_intersections(V, F, 1);
  if (!crossing.empty())
    fail<InputError>("the ", name, " intersects itself (faces ", crossing[0].first, " and ", crossing[0].second,
                     " cross): a morph needs shapes that do not overlap themselves");
}

Morph morph(const PointMatrix& source_points, const SimplexMatrix& source_faces, const PointMatrix& target_points,
            const SimplexMatrix& target_faces, const MorphOptions& options) {
  using Clock = std::chrono::steady_clock;
  Morph result;
  MorphReport& report = result.report;
  auto stage_start = Clock::now();
  auto stage = [&](const std::string& name, double fraction) {
    const auto now = Clock::now();
    report.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - stage_start).count());
    stage_start = now;
    if (options.progress && !options.progress(name, fraction)) throw Cancelled();
  };

  check_morph_input(source_points, source_faces, "source");
  check_morph_input(target_points, target_faces, "target");
  if (source_points.cols() != target_points.cols()) fail<InputError>("source and target must both be 2D or both 3D");
  if (!(options.t1 > options.t0)) fail<InputError>("the morph must run forward in time: t1 (", options.t1, ") <= t0 (", options.t0, ")");
  if (options.method == MorphMethod::Field) {
    StageClock clock(options);
    Morph result = field_morph(source_points, source_faces, target_points, target_faces, options, clock);
    clock.begin("validity", 0.9);
    zero_set_validity(result.manifold, result.report);
    const double size = std::max((source_points.colwise().maxCoeff() - source_points.colwise().minCoeff()).norm(),
                                 (target_points.colwise().maxCoeff() - target_points.colwise().minCoeff()).norm());
    end_distances(result.manifold, source_points, source_faces, target_points, target_faces, options, size,
                  result.report);
    double spent = 0;
    for (const auto& [name, seconds] : clock.seconds) spent += seconds;
    check_frames(result.manifold, options.t0, options.t1, source_points, source_faces, target_points, target_faces,
                 std::min(kValidityShare * spent, kValidityCap), result.report);
    clock.finish();
    result.report.stage_seconds = clock.seconds;
    return result;
  }
  const bool skeleton_method = options.method == MorphMethod::Skeleton;
  // Two layers (the source's after t0, the target's before t1) must leave the fill between them.
  if (!(options.max_push > 0 && options.max_push < 0.5))
    fail<InputError>("max_push must lie in (0, 0.5), got ", options.max_push);
  const int d = static_cast<int>(source_points.cols());
  // What the morph is built on: the inputs, their flat polygons fanned from
  // their centres (MorphOptions::fan_flat_polygons) — the same surfaces.
  // The ends are checked against the inputs as given (validity 2 below).
  FannedMesh source{source_points, source_faces}, target{target_points, target_faces};
  if (options.fan_flat_polygons && d == 3) {
    source = fan_flat_polygons(source_points, source_faces);
    target = fan_flat_polygons(target_points, target_faces);
  }
  report.source_fanned_polygons = source.polygons;
  report.target_fanned_polygons = target.polygons;
  const PointMatrix &VS = source.V, &VT = target.V;
  const SimplexMatrix &FS = source.F, &FT = target.F;

  // Inputs in general position. Cospherical points (a cube's square faces, a
  // regular torus) make the Delaunay fill ambiguous and Qhull merges such
  // facets into flat simplices, so the fill could miss faces of the
  // conforming surfaces. The combinatorics are therefore computed on points
  // perturbed by a small fraction of the size (kPerturbations: 1e-7, then
  // larger until the mesher and the fill conform), by offsets that are
  // functions of position (perturbation.hpp: vertices both inputs share stay
  // columns in time); the result gets the exact coordinates back
  // (restore_on_input), so the perturbation never shows. The planes t0 and t1
  // stay exactly flat (Qhull's own joggle would tilt them, and the part of
  // the fill in each plane would then no longer be one triangulation).
  const double size = std::max((VS.colwise().maxCoeff() - VS.colwise().minCoeff()).norm(),
                               (VT.colwise().maxCoeff() - VT.colwise().minCoeff()).norm());
  // The morph is solved over a time span proportional to the shapes' size,
  // then its time axis is mapped linearly onto t0..t1. A Delaunay fill is not
  // invariant under scaling one axis: solved over t0..t1 as given, the same
  // shapes would morph differently over 48 frames than over 1 second.
  const double span = kSolveSpan * std::max(size, 1e-300);
  // §8.6.1 step 1: the external skeletons, as free points (see morph_skeleton.hpp).
  PointMatrix KS(0, d), KT(0, d);
  if (skeleton_method) {
    KS = external_skeleton_points(VS, FS, 1e-3 * size);
    KT = external_skeleton_points(VT, FT, 1e-3 * size);
    // And over the flat sides of its hull that bridge a hole or a dent
    // (hull_cap_points): inputs with nothing outside them have no such side.
    for (auto [K, V, F, count] : {std::tuple<PointMatrix&, const PointMatrix&, const SimplexMatrix&, Index&>{
                                     KS, VS, FS, report.source_cap_points},
                                 {KT, VT, FT, report.target_cap_points}}) {
      if (K.rows() == 0) continue;
      const PointMatrix caps = hull_cap_points(V, F);
      count = caps.rows();
      PointMatrix both(K.rows() + caps.rows(), d);
      both << K, caps;
      K = std::move(both);
    }
    // Skeletons of symmetric shapes lie exactly in their symmetry planes,
    // with surface vertices (a torus's equator): moved off by 1e-4 of the
    // size — far more than the surface's perturbation below, and a tenth of
    // their least distance from the surface — cells joining them keep a
    // clear volume at the exact coordinates too.
    // By position (perturbation.hpp): a skeleton point both inputs share
    // stays one column.
    KS = perturbed_by_position(KS, 1e-4 * size, 1122);
    KT = perturbed_by_position(KT, 1e-4 * size, 1122);
  }
  report.source_skeleton_points = static_cast<Index>(KS.rows());
  report.target_skeleton_points = static_cast<Index>(KT.rows());
  if (skeleton_method) stage("skeleton", 0.1);

  PointMatrix P;  // the fill's points, perturbed: the geometry its combinatorics were decided on
  PointMatrix exact;  // the same points at their exact places (inputs restored, free points as in P)
  ConformingInput S, T;
  DelaunayTriangulation fill;
  SimplexMatrix target_constraints;
  Index nS = 0, nT = 0;
  double conform_seconds = 0;
  std::vector<std::pair<double, std::string>> mesher_errors;  // (perturbation, what failed) of the attempts
  // Polled while TetGen runs (MorphOptions::interrupted).
  const std::function<void()> while_meshing = interrupt_poll(options);
  hold_for_tests(options, "conforming");
  // §8.4 exactly where both inputs are convex (no exterior skeleton, checked
  // again there by exact predicates): the hull's own faces, no perturbation,
  // no mesher (morph_convex.hpp). Otherwise, or where that construction
  // refuses, the Delaunay fill below.
  std::optional<ConvexFill> convex_fill;
  if (skeleton_method && d == 3 && KS.rows() == 0 && KT.rows() == 0) {
    PointMatrix hull_points(VS.rows() + VT.rows(), d + 1);
    hull_points << VS, Eigen::VectorXd::Zero(VS.rows()), VT, Eigen::VectorXd::Constant(VT.rows(), span);
    convex_fill = convex_hull_fill(hull_points, VS.rows(), FS, (FT.array() + static_cast<int>(VS.rows())).matrix());
    if (convex_fill) {
      P = exact = convex_fill->points;
      nS = VS.rows(), nT = VT.rows();
      fill.simplices = convex_fill->simplices;
      S.fill.is_delaunay = T.fill.is_delaunay = true;  // no mesher: the inputs are their own refinement
      report.exact_convex_fill = true;
    }
  }
  for (const double scale : kPerturbations) {
    if (convex_fill) break;
    auto perturbed = [&](const PointMatrix& V) {
      return options.perturbation == Perturbation::HullFaces ? perturbed_along_hull_faces(V, scale * size, 20261122)
                                                  : perturbed_by_position(V, scale * size, 20261122);
    };
    const auto conform_start = Clock::now();
    // §8.6.1 step 2 (the strip method has no free points). A mesher that
    // returns a constrained, not conforming, fill may conform on points
    // perturbed further.
    const char* meshing = "source";
    try {
      S = conform_with_points(perturbed(VS), VS, FS, KS, "source", while_meshing);
      meshing = "target";
      T = conform_with_points(perturbed(VT), VT, FT, KT, "target", while_meshing);
    } catch (const Cancelled&) {
      throw;  // not a mesher's failure: no retry
    } catch (const std::runtime_error& e) {
      conform_seconds += std::chrono::duration<double>(Clock::now() - conform_start).count();
      std::string error = e.what();
      if (error.find(meshing) == std::string::npos) error = std::string("the ") + meshing + ": " + error;
      mesher_errors.emplace_back(scale, std::move(error));
      if (scale == kPerturbations.back()) fail<std::runtime_error>(failed_perturbations(mesher_errors));
      continue;
    }
    mesher_errors.clear();
    conform_seconds += std::chrono::duration<double>(Clock::now() - conform_start).count();
    if (options.progress && !options.progress("conforming", 0.3)) throw Cancelled();
    nS = static_cast<Index>(S.fill.points.rows()), nT = static_cast<Index>(T.fill.points.rows());
    P.resize(nS + nT, d + 1);
    P.topLeftCorner(nS, d) = S.fill.points;
    P.topRightCorner(nS, 1).setConstant(0.0);
    P.bottomLeftCorner(nT, d) = T.fill.points;
    P.bottomRightCorner(nT, 1).setConstant(span);
    exact = P;
    exact.topLeftCorner(nS, d) = S.exact_points;
    exact.bottomLeftCorner(nT, d) = T.exact_points;
    // The mesher's Steiner points lie exactly on the (perturbed) input edges
    // and faces: three collinear points, which Qhull's triangulation of a
    // degenerate facet can put in one flat simplex. Nudged off them by a
    // tenth of the perturbation — except those whose nudge would cost the
    // fill a refined face (nudged_steiner_points) — the fill still contains
    // the constraint faces (checked below) and has no such simplex. Where the
    // nudged fill still misses some (a cylinder whose caps are fans of
    // cocircular points: 4 of its 190 refined faces at 1e-7), the fill is
    // built once more on the mesher's own points before a larger
    // perturbation is tried (unnudged_steiner_points then counts them all).
    // With "hull_faces", the Steiner points on an input's hull stay too:
    // that perturbation keeps the hulls' degeneracies exact for the fill to
    // resolve, and a nudge brings them back — a Steiner point nudged off a
    // Blender cylinder's vertical hull edge made slivers with the edge's ends
    // that folded once restored (the frames into Blender's torus ran through
    // themselves at 2 of 5 checked times; a 64-sided cylinder -> the voxel
    // plate at 5 of 5, with 52 free vertices held back and a bubble of 5.8 %).
    std::vector<bool> source_stay, target_stay;
    if (options.perturbation == Perturbation::HullFaces) {
      source_stay = on_convex_hull(S.fill.points, VS);
      target_stay = on_convex_hull(T.fill.points, VT);
    }
    bool conforms = false;
    for (const bool nudging : {true, false}) {
      report.unnudged_steiner_points = 0;
      if (nudging) {
        const double nudge = 0.1 * scale * size;
        P.topLeftCorner(nS, d) = nudged_steiner_points(S.fill, VS.rows() + KS.rows(), nudge, report.unnudged_steiner_points,
                                                       source_stay);
        P.bottomLeftCorner(nT, d) =
            nudged_steiner_points(T.fill, VT.rows() + KT.rows(), nudge, report.unnudged_steiner_points, target_stay);
      } else {
        P.topLeftCorner(nS, d) = S.fill.points;
        P.bottomLeftCorner(nT, d) = T.fill.points;
        report.unnudged_steiner_points = (nS - VS.rows() - KS.rows()) + (nT - VT.rows() - KT.rows());
      }
      fill = options.fill == FillTriangulation::Qhull ? delaunay(P) : delaunay_exact(P);
      target_constraints = T.fill.constraints.array() + nS;
      report.perturbation = scale;
      // Flat simplices within one input's plane are harmless (they add
      // nothing); slivers on the hull's boundary are peeled off (where a facet
      // of the hull holds points of both planes: a flat side both inputs share,
      // a hull edge with collinear points); flat ones inside would leave holes.
      const FlatSimplices flats = peel_hull_slivers(fill, nS);
      report.flat_fill_simplices = options.fill == FillTriangulation::Qhull ? flats.inside : 0;  // CGAL's are proper: kept
      report.peeled_hull_slivers = flats.peeled;
      report.missing_source_faces = static_cast<Index>(missing_facets(fill.simplices, S.fill.constraints).size());
      report.missing_target_faces = static_cast<Index>(missing_facets(fill.simplices, target_constraints).size());
      conforms = report.flat_fill_simplices == 0 && report.missing_source_faces == 0 && report.missing_target_faces == 0;
      if (conforms) break;
    }
    if (conforms) break;
  }
  report.source_conforming = S.fill.is_delaunay;
  report.target_conforming = T.fill.is_delaunay;
  report.fill_simplices = static_cast<Index>(fill.simplices.rows());
  stage("fill", 0.6);
  // Report conforming and filling apart (they alternate in the retries above).
  report.stage_seconds.back().second -= conform_seconds;
  if (!convex_fill) report.stage_seconds.insert(report.stage_seconds.end() - 1, {"conforming", conform_seconds});
  if (report.missing_source_faces || report.missing_target_faces || report.flat_fill_simplices)
    fail<std::runtime_error>("the fill does not conform to the inputs (Theorem 5.2.1): ", report.missing_source_faces,
                             " source and ", report.missing_target_faces, " target faces are missing and ",
                             report.flat_fill_simplices, " simplices are flat");

  std::vector<bool> in_source(P.rows(), false), in_target(P.rows(), false);
  for (Index v = 0; v < nS; ++v) in_source[v] = true;
  for (Index v = nS; v < nS + nT; ++v) in_target[v] = true;
  if (convex_fill) in_source[convex_fill->source_centre] = in_target[convex_fill->target_centre] = true;
  SimplexMatrix A;
  SimplexMatrix boundary;  // of A, once it no longer changes (skeleton method)
  if (convex_fill) {
    A = fill.simplices;  // nothing outside either input: nothing to push or strip
  } else if (!skeleton_method) {
    // Sidedness is decided on the perturbed points, the geometry the fill
    // was built on: on the exact input, nearly planar quads (rounded
    // coordinates) would put apexes on either side at random, against the
    // fill's own combinatorics. Then the exact coordinates come back: input
    // vertices as given, added points on their input faces.
    const std::vector<bool> out_s = outside_of_constraint(P, fill.simplices, in_source, S.fill.constraints, &exact);
    const std::vector<bool> out_t = outside_of_constraint(P, fill.simplices, in_target, target_constraints, &exact);
    std::vector<Index> kept;
    for (Index s = 0; s < fill.simplices.rows(); ++s)
      if (!out_s[s] && !out_t[s]) kept.push_back(s);
    report.stripped_simplices = report.fill_simplices - static_cast<Index>(kept.size());
    A.resize(static_cast<Index>(kept.size()), d + 2);
    for (size_t r = 0; r < kept.size(); ++r) A.row(static_cast<Index>(r)) = fill.simplices.row(kept[r]);
    P = exact;
    stage("strip", 0.8);
  } else {
    // Nothing is stripped. Each plane's cells are classified as the fill
    // made them, on the perturbed points (the geometry its combinatorics
    // were decided on); then each plane with cells outside its input gets a
    // layer in which its free vertices are pushed into time (§8.6.3,
    // morph_layers.hpp), built on the exact coordinates. Where the exact
    // geometry is flat (cells of the inputs' planar quads, a facet of the
    // hull across both planes), the fill's simplices there are degenerate
    // (see the validity report).
    A = fill.simplices;
    PlaneCells source_plane = classify_plane(P, exact, A, in_source, S.fill.constraints, KS.rows() == 0);
    PlaneCells target_plane = classify_plane(P, exact, A, in_target, target_constraints, KT.rows() == 0);
    // Where the inputs coincide, what lies outside both is removed, not
    // pushed (shared_prisms); the planes are classified again.
    const std::vector<Prism> prism = shared_prisms(P, A, in_source, in_target, source_plane, target_plane);
    report.shared_stripped_simplices = std::count(prism.begin(), prism.end(), Prism::SharedOutside);
    report.inputs_coincide = std::find(prism.begin(), prism.end(), Prism::NotShared) == prism.end();
    if (report.shared_stripped_simplices > 0) {
      SimplexMatrix kept(A.rows() - report.shared_stripped_simplices, d + 2);
      for (Index s = 0, r = 0; s < A.rows(); ++s)
        if (prism[s] != Prism::SharedOutside) kept.row(r++) = A.row(s);
      A = std::move(kept);
      source_plane = classify_plane(P, exact, A, in_source, S.fill.constraints, KS.rows() == 0);
      target_plane = classify_plane(P, exact, A, in_target, target_constraints, KT.rows() == 0);
    }
    const std::vector<bool>& source_free = source_plane.free;
    const std::vector<bool>& target_free = target_plane.free;
    report.source_free_vertices = std::count(source_free.begin(), source_free.end(), true);
    report.target_free_vertices = std::count(target_free.begin(), target_free.end(), true);
    // §8.6.3: each plane with cells outside its input moves into time by the layer's
    // thickness (an affine map of the last axis: the fill stays positive),
    // and the layer between it and the end holds the push (morph_layers.hpp).
    // The fill's points get their exact coordinates back now; the layers are
    // built on them.
    const double thickness = options.max_push * span;
    // A plane needs a layer where any of its cells lies outside its input,
    // with a free vertex or not (the faces of those without are split).
    auto any_outside = [](const PlaneCells& plane) {
      return std::find(plane.outside.begin(), plane.outside.end(), true) != plane.outside.end();
    };
    const bool source_layer = any_outside(source_plane), target_layer = any_outside(target_plane);
    const double fill_t0 = source_layer ? thickness : 0.0, fill_t1 = target_layer ? span - thickness : span;
    const PointMatrix fill_points = P;
    for (Index v = 0; v < nS + nT; ++v) {
      P.row(v).head(d) = exact.row(v).head(d);
      P(v, d) = v < nS ? fill_t0 : fill_t1;
    }
    std::vector<SimplexMatrix> parts{A};
    for (auto [has_layer, plane, V, F, end, fill_time, ends, push] :
         {std::tuple<bool, const PlaneCells*, const PointMatrix*, const SimplexMatrix*, double, double, std::vector<bool>*,
                     std::array<double, 3>*>{source_layer, &source_plane, &VS, &FS, 0.0, fill_t0, &in_source,
                                             &report.source_push},
          {target_layer, &target_plane, &VT, &FT, span, fill_t1, &in_target, &report.target_push}}) {
      if (!has_layer) continue;
      const PlaneLayer layer = plane_layer(P, fill_points, *plane, *V, *F, end, fill_time);
      report.levelled_vertices += layer.levelled_vertices;
      report.split_faces += layer.split_faces;
      report.refinement_points += layer.refinement_points;
      report.peeled_slivers += layer.peeled_slivers;
      ends->assign(P.rows(), false);
      for (const Index v : layer.end_copies) (*ends)[v] = true;
      *push = {layer.smallest / span, layer.mean / span, layer.largest / span};
      report.sealed_vertices += layer.sealed_vertices;
      parts.push_back(layer.simplices);
    }
    in_source.resize(P.rows(), false), in_target.resize(P.rows(), false);
    Index rows = 0;
    for (const SimplexMatrix& part : parts) rows += part.rows();
    A.resize(rows, d + 2);
    rows = 0;
    for (const SimplexMatrix& part : parts) A.middleRows(rows, part.rows()) = part, rows += part.rows();
    boundary = boundary_facets(A);
    stage("push", 0.8);
  }

  // Validity 1, at the exact coordinates. Simplices that are not positive but
  // within restore_bound of zero are flat at the exact coordinates: cells of the
  // inputs' degenerate configurations (four coplanar or cocircular points)
  // whose sign the perturbation decided, as in simulation of simplicity.
  // Below it a simplex is inverted, which no rounding explains.
  report.simplices = static_cast<Index>(A.rows());
  const Eigen::VectorXd volumes = signed_volumes(P, A);
  report.min_volume = volumes.size() ? volumes.minCoeff() : 0.0;
  const double moved = restored_distance(d, report.perturbation, size);
  report.min_relative_volume = volumes.size() ? std::numeric_limits<double>::infinity() : 0.0;
  double factorial = 1;
  for (int i = 2; i <= d + 1; ++i) factorial *= i;
  for (Index s = 0; s < volumes.size(); ++s) {
    const double longest = longest_edge(P, A.row(s).data(), d + 2);
    const double determinant = volumes(s) * factorial;  // the sign convention of signed_volumes
    report.min_relative_volume = std::min(report.min_relative_volume, determinant / std::pow(longest, d + 1));
    if (determinant < -restore_bound(longest, d + 1, moved)) ++report.inverted_simplices;
    else if (determinant <= 0) ++report.degenerate_simplices;
  }

  // The animation manifold: the boundary of what remains, less the caps
  // (facets all of whose corners stay in one input's plane).
  const SimplexMatrix B = boundary.rows() ? std::move(boundary) : boundary_facets(A);
  std::vector<Index> lateral;
  for (Index f = 0; f < B.rows(); ++f) {
    bool all_start = true, all_end = true;
    for (int c = 0; c < d + 1; ++c) all_start = all_start && in_source[B(f, c)], all_end = all_end && in_target[B(f, c)];
    if (!all_start && !all_end) lateral.push_back(f);
  }
  // Solved time 0..span onto t0..t1, the planes exactly.
  result.manifold.V = P;
  for (Index v = 0; v < P.rows(); ++v) {
    const double solved = P(v, d);
    result.manifold.V(v, d) = solved <= 0.0    ? options.t0
                              : solved >= span ? options.t1
                                               : options.t0 + (options.t1 - options.t0) * (solved / span);
  }
  result.manifold.S.resize(static_cast<Index>(lateral.size()), d + 1);
  for (size_t r = 0; r < lateral.size(); ++r) {
    result.manifold.S.row(static_cast<Index>(r)) = B.row(lateral[r]);
    // Outward facets of positive simplices in R^4 face the other way from the
    // stitched convention (the tent orientation of stitch.hpp), those in R^3
    // the same way (the wedge product's sign alternates with the dimension,
    // see stitch.cpp): turn them in R^4 so slices face outward in both.
    if (d == 3) std::swap(result.manifold.S(static_cast<Index>(r), 0), result.manifold.S(static_cast<Index>(r), 1));
  }
  stage("boundary", 0.9);

  end_distances(result.manifold, source_points, source_faces, target_points, target_faces, options, size, report);
  stage("validity", 1.0);
  return result;
}

}  // namespace animanifold
