#include "animanifold/morph.hpp"

#include "animanifold/coordinate_bound.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/flat_polygons.hpp"
#include "morph_convex.hpp"
#include "morph_layers.hpp"
#include "morph_skeleton.hpp"
#include "animanifold/perturbation.hpp"
#include "animanifold/self_intersection.hpp"
#include "animanifold/shelling.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/surface_distance.hpp"
#include "animanifold/threads.hpp"
#include "morph_field.hpp"
#include "morph_stages.hpp"
#include "animanifold/morph_validity.hpp"

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

// longest_edge of every simplex of S, each into its own entry (the same for any thread count).
Eigen::VectorXd longest_edges(const PointMatrix& P, const SimplexMatrix& S) {
  Eigen::VectorXd longest(S.rows());
  const int count = static_cast<int>(S.cols());
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) longest(s) = longest_edge(P, S.row(s).data(), count);
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
  const Slice start = slice_shape(manifold, d, options.t0), end = slice_shape(manifold, d, options.t1);
  report.source_distance = two_sided(start, VS, FS);
  report.target_distance = two_sided(end, VT, FT);
  report.ends_reproduced = report.source_distance <= 1e-9 && report.target_distance <= 1e-9;
}

// Validity of a manifold extracted as a zero set (the field method): it is a
// closed oriented manifold but for its ends, and no tet is flat (its volume
// relative to its longest edge cubed). One pass over the tets, nothing kept:
// the volume from the wedge product's length (as simplex_normals), not the
// Gram determinant, whose square loses half the digits of a thin tet. Time is
// scaled by `time_scale` (the shapes' size over the range), so that a tet's
// flatness does not depend on the frame range the user morphs over: over
// frames 1-250 a tet's longest edge would be its time extent.
void zero_set_validity(const Complex& manifold, double time_scale, MorphReport& report) {
  const ManifoldReport check = check_manifold(manifold.S);
  report.inverted_simplices = check.misoriented_facets + check.nonmanifold_facets;
  const PointMatrix& V = manifold.V;
  const SimplexMatrix& S = manifold.S;
  if (V.cols() != 4 || S.cols() != 4) fail<InputError>("a zero set in R^4 has tets, got ", S.cols(), " corners in R^", V.cols());
  double min_volume = S.rows() ? std::numeric_limits<double>::infinity() : 0.0;
  double min_relative = min_volume;
  Index degenerate = 0;
  for (Index s = 0; s < S.rows(); ++s) {
    const Index* c = S.row(s).data();
    Eigen::Matrix<double, 4, 4> corner;
    for (int k = 0; k < 4; ++k) corner.row(k) = V.row(c[k]);
    corner.col(3) *= time_scale;
    Eigen::Matrix<double, 3, 4> edges;
    for (int k = 0; k < 3; ++k) edges.row(k) = corner.row(k + 1) - corner.row(0);
    Eigen::Vector4d normal;
    for (int j = 0; j < 4; ++j) {  // the wedge product of the three edges
      Eigen::Matrix3d minor;
      for (int col = 0, m = 0; col < 4; ++col)
        if (col != j) minor.col(m++) = edges.col(col);
      normal(j) = (j % 2 ? -1.0 : 1.0) * minor.determinant();
    }
    const double volume = normal.norm() / 6.0;
    double longest = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (corner.row(a) - corner.row(b)).squaredNorm());
    longest = std::sqrt(longest);
    const double relative = longest > 0 ? volume / (longest * longest * longest) : 0.0;
    min_volume = std::min(min_volume, volume);
    min_relative = std::min(min_relative, relative);
    degenerate += relative <= 1e-14;
  }
  report.min_volume = min_volume, report.min_relative_volume = min_relative;
  report.degenerate_simplices = degenerate;
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
    for (int c = 0; c < d; ++c) {
      if (!std::isfinite(V(v, c))) fail<InputError>("the ", name, "'s vertex ", v, " is not finite");
      if (std::abs(V(v, c)) > kMaxCoordinate)
        fail<InputError>("the ", name, "'s vertex ", v, " has a coordinate of ", V(v, c), ": a morph takes coordinates within +-",
                         kMaxCoordinate, " (scale the shape down)");
    }
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

namespace {

// The seed's methods (skeleton, strip), stage by stage. Each stage reads what
// the earlier ones left here and adds its own part; morph() runs them in
// order and times each under its stage name.
struct SeedMorph {
  const MorphOptions& options;
  MorphReport& report;
  const PointMatrix &VS, &VT;  // the inputs, flat polygons fanned
  const SimplexMatrix &FS, &FT;
  int d = 0;             // of the inputs' space
  double size = 0;       // the inputs' larger bounding-box diagonal
  double span = 0;       // the solved time range (kSolveSpan of the size)
  bool skeleton = false;  // the skeleton method (else strip)

  PointMatrix KS, KT;  // free points: the external skeletons and hull caps ("skeleton")
  // "conforming" and "fill":
  PointMatrix P;      // the fill's points, perturbed: the geometry its combinatorics were decided on
  PointMatrix exact;  // the same points at their exact places (inputs restored, free points as in P)
  ConformingInput S, T;
  DelaunayTriangulation fill;
  SimplexMatrix target_constraints;  // T's refined faces, numbered in P
  Index nS = 0, nT = 0;              // P's rows from S's plane, then T's
  std::optional<ConvexFill> convex_fill;
  double conform_seconds = 0;
  // "strip" or "push": the filled shape A, its points' planes, and its boundary once known.
  std::vector<bool> in_source, in_target;
  SimplexMatrix A, boundary;
};

// §8.6.1 step 1: the external skeletons as free points (morph_skeleton.hpp),
// and points over the flat sides of each hull that bridge a hole or a dent
// (hull_cap_points): inputs with nothing outside them have no such side.
void find_free_points(SeedMorph& m) {
  m.KS = PointMatrix(0, m.d), m.KT = PointMatrix(0, m.d);
  if (m.skeleton) {
    m.KS = external_skeleton_points(m.VS, m.FS, 1e-3 * m.size);
    m.KT = external_skeleton_points(m.VT, m.FT, 1e-3 * m.size);
    for (auto [K, V, F, count] : {std::tuple<PointMatrix&, const PointMatrix&, const SimplexMatrix&, Index&>{
                                     m.KS, m.VS, m.FS, m.report.source_cap_points},
                                 {m.KT, m.VT, m.FT, m.report.target_cap_points}}) {
      if (K.rows() == 0) continue;
      const PointMatrix caps = hull_cap_points(V, F);
      count = caps.rows();
      PointMatrix both(K.rows() + caps.rows(), m.d);
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
    m.KS = perturbed_by_position(m.KS, 1e-4 * m.size, 1122);
    m.KT = perturbed_by_position(m.KT, 1e-4 * m.size, 1122);
  }
  m.report.source_skeleton_points = static_cast<Index>(m.KS.rows());
  m.report.target_skeleton_points = static_cast<Index>(m.KT.rows());
}

// §8.4 exactly where both inputs are convex (no exterior skeleton, checked
// again there by exact predicates): the hull's own faces, no perturbation,
// no mesher (morph_convex.hpp). False where that construction refuses: the
// Delaunay fill then follows.
bool fill_convex_hull(SeedMorph& m) {
  if (!m.skeleton || m.d != 3 || m.KS.rows() != 0 || m.KT.rows() != 0) return false;
  PointMatrix hull_points(m.VS.rows() + m.VT.rows(), m.d + 1);
  hull_points << m.VS, Eigen::VectorXd::Zero(m.VS.rows()), m.VT, Eigen::VectorXd::Constant(m.VT.rows(), m.span);
  m.convex_fill =
      convex_hull_fill(hull_points, m.VS.rows(), m.FS, (m.FT.array() + static_cast<int>(m.VS.rows())).matrix());
  if (!m.convex_fill) return false;
  m.P = m.exact = m.convex_fill->points;
  m.nS = m.VS.rows(), m.nT = m.VT.rows();
  m.fill.simplices = m.convex_fill->simplices;
  m.S.fill.is_delaunay = m.T.fill.is_delaunay = true;  // no mesher: the inputs are their own refinement
  m.report.exact_convex_fill = true;
  return true;
}

// The Delaunay fill of P (the two conforming planes), first with the mesher's
// Steiner points nudged, then on its own points; true once it conforms
// (Theorem 5.2.1: every refined face in it, no flat simplex inside).
//
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
// With HullFaces, the Steiner points on an input's hull stay too:
// that perturbation keeps the hulls' degeneracies exact for the fill to
// resolve, and a nudge brings them back — a Steiner point nudged off a
// Blender cylinder's vertical hull edge made slivers with the edge's ends
// that folded once restored (the frames into Blender's torus ran through
// themselves at 2 of 5 checked times; a 64-sided cylinder -> the voxel
// plate at 5 of 5, with 52 free vertices held back and a bubble of 5.8 %).
bool fill_conforming_planes(SeedMorph& m, double scale) {
  MorphReport& report = m.report;
  std::vector<bool> source_stay, target_stay;
  if (m.options.perturbation == Perturbation::HullFaces) {
    source_stay = on_convex_hull(m.S.fill.points, m.VS);
    target_stay = on_convex_hull(m.T.fill.points, m.VT);
  }
  const Index source_fixed = m.VS.rows() + m.KS.rows(), target_fixed = m.VT.rows() + m.KT.rows();
  for (const bool nudging : {true, false}) {
    report.unnudged_steiner_points = 0;
    if (nudging) {
      const double nudge = 0.1 * scale * m.size;
      m.P.topLeftCorner(m.nS, m.d) =
          nudged_steiner_points(m.S.fill, source_fixed, nudge, report.unnudged_steiner_points, source_stay);
      m.P.bottomLeftCorner(m.nT, m.d) =
          nudged_steiner_points(m.T.fill, target_fixed, nudge, report.unnudged_steiner_points, target_stay);
    } else {
      m.P.topLeftCorner(m.nS, m.d) = m.S.fill.points;
      m.P.bottomLeftCorner(m.nT, m.d) = m.T.fill.points;
      report.unnudged_steiner_points = (m.nS - source_fixed) + (m.nT - target_fixed);
    }
    m.fill = m.options.fill == FillTriangulation::Qhull ? delaunay(m.P) : delaunay_exact(m.P);
    m.target_constraints = m.T.fill.constraints.array() + m.nS;
    report.perturbation = scale;
    // Flat simplices within one input's plane are harmless (they add
    // nothing); slivers on the hull's boundary are peeled off (where a facet
    // of the hull holds points of both planes: a flat side both inputs share,
    // a hull edge with collinear points); flat ones inside would leave holes.
    const FlatSimplices flats = peel_hull_slivers(m.fill, m.nS);
    report.flat_fill_simplices =
        m.options.fill == FillTriangulation::Qhull ? flats.inside : 0;  // CGAL's are proper: kept
    report.peeled_hull_slivers = flats.peeled;
    report.missing_source_faces = static_cast<Index>(missing_facets(m.fill.simplices, m.S.fill.constraints).size());
    report.missing_target_faces = static_cast<Index>(missing_facets(m.fill.simplices, m.target_constraints).size());
    if (report.flat_fill_simplices == 0 && report.missing_source_faces == 0 && report.missing_target_faces == 0)
      return true;
  }
  return false;
}

// P and its exact twin from the two conforming planes: S's at time 0, T's at
// the span.
void stack_planes(SeedMorph& m) {
  m.nS = static_cast<Index>(m.S.fill.points.rows()), m.nT = static_cast<Index>(m.T.fill.points.rows());
  m.P.resize(m.nS + m.nT, m.d + 1);
  m.P.topLeftCorner(m.nS, m.d) = m.S.fill.points;
  m.P.topRightCorner(m.nS, 1).setConstant(0.0);
  m.P.bottomLeftCorner(m.nT, m.d) = m.T.fill.points;
  m.P.bottomRightCorner(m.nT, 1).setConstant(m.span);
  m.exact = m.P;
  m.exact.topLeftCorner(m.nS, m.d) = m.S.exact_points;
  m.exact.bottomLeftCorner(m.nT, m.d) = m.T.exact_points;
}

// Inputs in general position, made conforming Delaunay (§8.6.1 step 2: with
// their free points; the strip method has none), then filled. Cospherical
// points (a cube's square faces, a regular torus) make the Delaunay fill
// ambiguous and Qhull merges such facets into flat simplices, so the fill
// could miss faces of the conforming surfaces. The combinatorics are
// therefore computed on points perturbed by a small fraction of the size
// (kPerturbations: 1e-7, then larger until the mesher and the fill conform),
// by offsets that are functions of position (perturbation.hpp: vertices both
// inputs share stay columns in time); the result gets the exact coordinates
// back (restore_on_input), so the perturbation never shows. The planes t0
// and t1 stay exactly flat (Qhull's own joggle would tilt them, and the part
// of the fill in each plane would then no longer be one triangulation).
// A mesher that returns a constrained, not conforming, fill may conform on
// points perturbed further. Throws MeshingError listing every
// attempt's failure when none conforms.
void conform_and_fill(SeedMorph& m) {
  using Clock = std::chrono::steady_clock;
  std::vector<std::pair<double, std::string>> mesher_errors;  // (perturbation, what failed) of the attempts
  const std::function<void()> while_meshing = interrupt_poll(m.options);  // polled while TetGen runs
  for (const double scale : kPerturbations) {
    auto perturbed = [&](const PointMatrix& V) {
      return m.options.perturbation == Perturbation::HullFaces ? perturbed_along_hull_faces(V, scale * m.size, 20261122)
                                                               : perturbed_by_position(V, scale * m.size, 20261122);
    };
    const auto conform_start = Clock::now();
    const char* meshing = "source";
    try {
      m.S = conform_with_points(perturbed(m.VS), m.VS, m.FS, m.KS, "source", while_meshing,
                                m.options.mesher_time_limit);
      meshing = "target";
      m.T = conform_with_points(perturbed(m.VT), m.VT, m.FT, m.KT, "target", while_meshing,
                                m.options.mesher_time_limit);
    } catch (const Cancelled&) {
      throw;  // not a mesher's failure: no retry
    } catch (const TimeLimitError& e) {
      // Not the input's verdict: the next perturbation would give another
      // result, chosen by the machine's speed. Fail, naming the input.
      fail<TimeLimitError>("the ", meshing, " cannot be meshed at perturbation ", scale, ": ", e.what());
    } catch (const std::runtime_error& e) {
      m.conform_seconds += std::chrono::duration<double>(Clock::now() - conform_start).count();
      std::string error = e.what();
      if (error.find(meshing) == std::string::npos) error = std::string("the ") + meshing + ": " + error;
      mesher_errors.emplace_back(scale, std::move(error));
      if (scale == kPerturbations.back()) fail<MeshingError>(failed_perturbations(mesher_errors));
      continue;
    }
    mesher_errors.clear();
    m.conform_seconds += std::chrono::duration<double>(Clock::now() - conform_start).count();
    if (m.options.interrupter.progress && !m.options.interrupter.progress("conforming", 0.3)) throw Cancelled();
    stack_planes(m);
    if (fill_conforming_planes(m, scale)) break;
  }
}

// §8.5: the fill less its simplices whose projection lies outside either
// input. Sidedness is decided on the perturbed points, the geometry the fill
// was built on: on the exact input, nearly planar quads (rounded
// coordinates) would put apexes on either side at random, against the
// fill's own combinatorics. Then the exact coordinates come back: input
// vertices as given, added points on their input faces.
void strip_outside(SeedMorph& m) {
  const SimplexMatrix& simplices = m.fill.simplices;
  const std::vector<bool> out_s = outside_of_constraint(m.P, simplices, m.in_source, m.S.fill.constraints, &m.exact);
  const std::vector<bool> out_t = outside_of_constraint(m.P, simplices, m.in_target, m.target_constraints, &m.exact);
  std::vector<Index> kept;
  for (Index s = 0; s < simplices.rows(); ++s)
    if (!out_s[s] && !out_t[s]) kept.push_back(s);
  m.report.stripped_simplices = m.report.fill_simplices - static_cast<Index>(kept.size());
  m.A.resize(static_cast<Index>(kept.size()), m.d + 2);
  for (size_t r = 0; r < kept.size(); ++r) m.A.row(static_cast<Index>(r)) = simplices.row(kept[r]);
  m.P = m.exact;
}

// Each plane's cells, classified as the fill made them, on the perturbed
// points (the geometry its combinatorics were decided on). Where the inputs
// coincide, what lies outside both is removed from A, not pushed
// (shared_prisms), and the planes are classified again.
std::pair<PlaneCells, PlaneCells> classify_planes(SeedMorph& m) {
  auto classify = [&] {
    return std::pair{classify_plane(m.P, m.exact, m.A, m.in_source, m.S.fill.constraints, m.KS.rows() == 0),
                     classify_plane(m.P, m.exact, m.A, m.in_target, m.target_constraints, m.KT.rows() == 0)};
  };
  auto planes = classify();
  const std::vector<Prism> prism = shared_prisms(m.P, m.A, m.in_source, m.in_target, planes.first, planes.second);
  m.report.shared_stripped_simplices = std::count(prism.begin(), prism.end(), Prism::SharedOutside);
  m.report.inputs_coincide = std::find(prism.begin(), prism.end(), Prism::NotShared) == prism.end();
  if (m.report.shared_stripped_simplices == 0) return planes;
  SimplexMatrix kept(m.A.rows() - m.report.shared_stripped_simplices, m.d + 2);
  for (Index s = 0, r = 0; s < m.A.rows(); ++s)
    if (prism[s] != Prism::SharedOutside) kept.row(r++) = m.A.row(s);
  m.A = std::move(kept);
  return classify();
}

// §8.6.3: nothing is stripped; each plane with cells outside its input (with
// a free vertex or not: the faces of those without are split) moves into
// time by the layer's thickness (an affine map of the last axis: the fill
// stays positive), and the layer between it and the end holds the push of
// its free vertices (morph_layers.hpp), built on the exact coordinates.
// Where the exact geometry is flat (cells of the inputs' planar quads, a
// facet of the hull across both planes), the fill's simplices there are
// degenerate (see the validity report).
void push_free_points(SeedMorph& m) {
  MorphReport& report = m.report;
  m.A = m.fill.simplices;
  const auto [source_plane, target_plane] = classify_planes(m);
  report.source_free_vertices = std::count(source_plane.free.begin(), source_plane.free.end(), true);
  report.target_free_vertices = std::count(target_plane.free.begin(), target_plane.free.end(), true);
  const double thickness = m.options.max_push * m.span;
  auto any_outside = [](const PlaneCells& plane) {
    return std::find(plane.outside.begin(), plane.outside.end(), true) != plane.outside.end();
  };
  const bool source_layer = any_outside(source_plane), target_layer = any_outside(target_plane);
  const double fill_t0 = source_layer ? thickness : 0.0, fill_t1 = target_layer ? m.span - thickness : m.span;
  const PointMatrix fill_points = m.P;
  for (Index v = 0; v < m.nS + m.nT; ++v) {
    m.P.row(v).head(m.d) = m.exact.row(v).head(m.d);
    m.P(v, m.d) = v < m.nS ? fill_t0 : fill_t1;
  }
  std::vector<SimplexMatrix> parts{m.A};
  for (auto [has_layer, plane, V, F, end, fill_time, ends, push] :
       {std::tuple<bool, const PlaneCells*, const PointMatrix*, const SimplexMatrix*, double, double, std::vector<bool>*,
                   std::array<double, 3>*>{source_layer, &source_plane, &m.VS, &m.FS, 0.0, fill_t0, &m.in_source,
                                           &report.source_push},
        {target_layer, &target_plane, &m.VT, &m.FT, m.span, fill_t1, &m.in_target, &report.target_push}}) {
    if (!has_layer) continue;
    const PlaneLayer layer = plane_layer(m.P, fill_points, *plane, *V, *F, end, fill_time);
    report.levelled_vertices += layer.levelled_vertices;
    report.split_faces += layer.split_faces;
    report.refinement_points += layer.refinement_points;
    report.peeled_slivers += layer.peeled_slivers;
    ends->assign(m.P.rows(), false);
    for (const Index v : layer.end_copies) (*ends)[v] = true;
    *push = {layer.smallest / m.span, layer.mean / m.span, layer.largest / m.span};
    report.sealed_vertices += layer.sealed_vertices;
    parts.push_back(layer.simplices);
  }
  m.in_source.resize(m.P.rows(), false), m.in_target.resize(m.P.rows(), false);
  Index rows = 0;
  for (const SimplexMatrix& part : parts) rows += part.rows();
  m.A.resize(rows, m.d + 2);
  rows = 0;
  for (const SimplexMatrix& part : parts) m.A.middleRows(rows, part.rows()) = part, rows += part.rows();
  m.boundary = boundary_facets(m.A);
}

// Validity 1, at the exact coordinates. Simplices that are not positive but
// within restore_bound of zero are flat at the exact coordinates: cells of the
// inputs' degenerate configurations (four coplanar or cocircular points)
// whose sign the perturbation decided, as in simulation of simplicity.
// Below it a simplex is inverted, which no rounding explains.
void count_flat_and_inverted(SeedMorph& m) {
  MorphReport& report = m.report;
  const int d = m.d;
  report.simplices = static_cast<Index>(m.A.rows());
  const Eigen::VectorXd volumes = signed_volumes(m.P, m.A);
  report.min_volume = volumes.size() ? volumes.minCoeff() : 0.0;
  const double moved = restored_distance(d, report.perturbation, m.size);
  report.min_relative_volume = volumes.size() ? std::numeric_limits<double>::infinity() : 0.0;
  double factorial = 1;
  for (int i = 2; i <= d + 1; ++i) factorial *= i;
  const Eigen::VectorXd longest_edge = longest_edges(m.P, m.A);
  for (Index s = 0; s < volumes.size(); ++s) {
    const double longest = longest_edge(s);
    const double determinant = volumes(s) * factorial;  // the sign convention of signed_volumes
    report.min_relative_volume = std::min(report.min_relative_volume, determinant / std::pow(longest, d + 1));
    if (determinant < -restore_bound(longest, d + 1, moved)) ++report.inverted_simplices;
    else if (determinant <= 0) ++report.degenerate_simplices;
  }
}

// The animation manifold: the boundary of A, less the caps (facets all of
// whose corners stay in one input's plane), with the solved time 0..span
// mapped onto t0..t1 (the planes exactly).
Complex lateral_boundary(SeedMorph& m) {
  const int d = m.d;
  const SimplexMatrix B = m.boundary.rows() ? std::move(m.boundary) : boundary_facets(m.A);
  std::vector<Index> lateral;
  for (Index f = 0; f < B.rows(); ++f) {
    bool all_start = true, all_end = true;
    for (int c = 0; c < d + 1; ++c) all_start = all_start && m.in_source[B(f, c)], all_end = all_end && m.in_target[B(f, c)];
    if (!all_start && !all_end) lateral.push_back(f);
  }
  Complex manifold;
  manifold.V = m.P;
  const MorphOptions& o = m.options;
  for (Index v = 0; v < m.P.rows(); ++v) {
    const double solved = m.P(v, d);
    manifold.V(v, d) = solved <= 0.0 ? o.t0 : solved >= m.span ? o.t1 : o.t0 + (o.t1 - o.t0) * (solved / m.span);
  }
  manifold.S.resize(static_cast<Index>(lateral.size()), d + 1);
  for (size_t r = 0; r < lateral.size(); ++r) {
    manifold.S.row(static_cast<Index>(r)) = B.row(lateral[r]);
    // Outward facets of positive simplices in R^4 face the other way from the
    // stitched convention (the tent orientation of stitch.hpp), those in R^3
    // the same way (the wedge product's sign alternates with the dimension,
    // see stitch.cpp): turn them in R^4 so slices face outward in both.
    if (d == 3) std::swap(manifold.S(static_cast<Index>(r), 0), manifold.S(static_cast<Index>(r), 1));
  }
  return manifold;
}

// Spread frames the field method checks for crossings (morph_validity.hpp)
// when its space-time triangulation is certified embedded: the middle one,
// an independent check of the certificate (and of the extraction and the
// slicing) on a frame the user gets. When it is not, all 24 are checked.
// CGAL's self-intersection test costs 10-25 times a frame's slicing and
// topology: all 24 would cost two thirds of the morph's own time, and even
// the quarters' two more a tenth, against the 25 % all checks may take.
constexpr int kConfirmingCrossingFrames = 1;

// Frames the field method checks inside its fill slab, beside the spread
// ones: the Delaunay fill joins two samplings of the field there, in less
// than the spread frames' spacing, and can change the frames' topology
// between them (pieces, handles for a moment) where neither does.
constexpr int kFillSlabFrames = 7;

// kFillSlabFrames times evenly inside the fill slab (none for a sweep).
std::vector<double> fill_slab_frames(const SpaceTimeTriangulation& space_time) {
  if (space_time.source.times.empty() || space_time.target.times.empty()) return {};
  const double from = space_time.source.times.back(), to = space_time.target.times.back();
  std::vector<double> times;
  for (int k = 1; k <= kFillSlabFrames; ++k) times.push_back(from + (to - from) * k / (kFillSlabFrames + 1));
  return times;
}

// The field method (morph_field.hpp) and its checks (morph_validity.hpp).
Morph field_method(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT, const SimplexMatrix& FT,
                   const MorphOptions& options) {
  StageClock clock(options);
  FieldMorph field;
  SpaceTimeCertificate certificate;
  std::optional<Complex> swept = swept_when_same(VS, FS, VT, FT, options.t0, options.t1);
  if (swept) {
    clock.begin("sweep", 0.1);
    field.morph.manifold = std::move(*swept);
    field.morph.report.inputs_coincide = true;
    // Every frame is S, which morph()'s input checks found free of crossings.
    certificate.embedded = true;
  } else {
    field = field_morph(VS, FS, VT, FT, options, clock);
  }
  Morph result = std::move(field.morph);
  clock.begin("validity", 0.9);
  const double size = std::max((VS.colwise().maxCoeff() - VS.colwise().minCoeff()).norm(),
                               (VT.colwise().maxCoeff() - VT.colwise().minCoeff()).norm());
  // The checks of the simplices, the ends and the space-time triangulation
  // write other fields of the report than the frames' checks, which they run
  // beside.
  check_frames(
      result.manifold, options.t0, options.t1, VS, FS, VT, FT, result.report,
      {[&] {
         if (!swept) certificate = certify_space_time(field.space_time, &field.covers);
       },
       [&] { zero_set_validity(result.manifold, size / (options.t1 - options.t0), result.report); },
       [&] { end_distances(result.manifold, VS, FS, VT, FT, options, size, result.report); }},
      kConfirmingCrossingFrames, [&] { return !certificate.embedded; }, fill_slab_frames(field.space_time));
  result.report.crossings_certified = certificate.embedded;
  result.report.certificate_failure = certificate.failure;
  clock.finish();
  result.report.stage_seconds = clock.seconds;
  return result;
}

}  // namespace

Morph morph(const PointMatrix& source_points, const SimplexMatrix& source_faces, const PointMatrix& target_points,
            const SimplexMatrix& target_faces, const MorphOptions& options) {
  check_morph_input(source_points, source_faces, "source");
  check_morph_input(target_points, target_faces, "target");
  if (source_points.cols() != target_points.cols()) fail<InputError>("source and target must both be 2D or both 3D");
  for (const auto& [label, t] : {std::pair{"t0", options.t0}, std::pair{"t1", options.t1}})
    if (!(std::abs(t) <= kMaxCoordinate))
      fail<InputError>("the morph's ", label, " is ", t, ": times must lie within +-", kMaxCoordinate);
  if (!(options.t1 > options.t0))
    fail<InputError>("the morph must run forward in time: t1 (", options.t1, ") <= t0 (", options.t0, ")");
  if (options.method == MorphMethod::Field)
    return field_method(source_points, source_faces, target_points, target_faces, options);
  // Two layers (the source's after t0, the target's before t1) must leave the fill between them.
  if (!(options.max_push > 0 && options.max_push < 0.5))
    fail<InputError>("max_push must lie in (0, 0.5), got ", options.max_push);

  using Clock = std::chrono::steady_clock;
  Morph result;
  MorphReport& report = result.report;
  auto stage_start = Clock::now();
  auto stage = [&](const std::string& name, double fraction) {  // `name` has finished
    const auto now = Clock::now();
    report.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - stage_start).count());
    stage_start = now;
    if (options.interrupter.progress && !options.interrupter.progress(name, fraction)) throw Cancelled();
  };
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
  SeedMorph m{options, report, source.V, target.V, source.F, target.F};
  m.d = d;
  m.size = std::max((m.VS.colwise().maxCoeff() - m.VS.colwise().minCoeff()).norm(),
                    (m.VT.colwise().maxCoeff() - m.VT.colwise().minCoeff()).norm());
  m.span = kSolveSpan * std::max(m.size, 1e-300);
  m.skeleton = options.method == MorphMethod::Skeleton;

  find_free_points(m);
  if (m.skeleton) stage("skeleton", 0.1);
  hold_for_tests(options, "conforming");
  if (!fill_convex_hull(m)) conform_and_fill(m);
  report.source_conforming = m.S.fill.is_delaunay;
  report.target_conforming = m.T.fill.is_delaunay;
  report.fill_simplices = static_cast<Index>(m.fill.simplices.rows());
  stage("fill", 0.6);
  // Report conforming and filling apart (they alternate in the retries).
  report.stage_seconds.back().second -= m.conform_seconds;
  if (!m.convex_fill) report.stage_seconds.insert(report.stage_seconds.end() - 1, {"conforming", m.conform_seconds});
  if (report.missing_source_faces || report.missing_target_faces || report.flat_fill_simplices)
    fail<MeshingError>("the fill does not conform to the inputs (Theorem 5.2.1): ", report.missing_source_faces,
                             " source and ", report.missing_target_faces, " target faces are missing and ",
                             report.flat_fill_simplices, " simplices are flat");

  m.in_source.assign(m.P.rows(), false), m.in_target.assign(m.P.rows(), false);
  for (Index v = 0; v < m.nS; ++v) m.in_source[v] = true;
  for (Index v = m.nS; v < m.nS + m.nT; ++v) m.in_target[v] = true;
  if (m.convex_fill) m.in_source[m.convex_fill->source_centre] = m.in_target[m.convex_fill->target_centre] = true;
  if (m.convex_fill) {
    m.A = m.fill.simplices;  // nothing outside either input: nothing to push or strip
  } else if (!m.skeleton) {
    strip_outside(m);
    stage("strip", 0.8);
  } else {
    push_free_points(m);
    stage("push", 0.8);
  }
  count_flat_and_inverted(m);
  result.manifold = lateral_boundary(m);
  stage("boundary", 0.9);
  end_distances(result.manifold, source_points, source_faces, target_points, target_faces, options, m.size, report);
  if (d == 3)  // the frames' checks, as the field method's (2D: the Python morph's own)
    check_frames(result.manifold, options.t0, options.t1, source_points, source_faces, target_points, target_faces,
                 report);
  stage("validity", 1.0);
  return result;
}

}  // namespace animanifold
