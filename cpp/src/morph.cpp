#include "animanifold/morph.hpp"

#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/hole_space.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/surface_distance.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <random>
#include <unordered_map>

namespace animanifold {

namespace {

using Key = std::array<Index, 5>;  // a sorted vertex set, padded with -1

Key make_key(const Index* ids, int count) {
  Key key;
  key.fill(-1);
  std::copy(ids, ids + count, key.begin());
  std::sort(key.begin(), key.begin() + count);
  return key;
}

struct KeyHash {
  size_t operator()(const Key& k) const {
    size_t h = 1469598103934665603ull;
    for (Index v : k) h = (h ^ static_cast<size_t>(static_cast<std::uint32_t>(v))) * 1099511628211ull;
    return h;
  }
};

// A closed, consistently oriented, outward shape, or an InputError naming what is wrong.
void check_closed_shape(const PointMatrix& V, const SimplexMatrix& F, const char* name) {
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
}

ConformingDelaunay conform(const PointMatrix& V, const SimplexMatrix& F) {
  return V.cols() == 3 ? conforming_delaunay_3d(V, F) : conforming_delaunay_2d(V, F);
}

// The conforming surface was built on perturbed input (`perturbed`); give
// input vertices their exact coordinates back and put every added point on
// the input face it lies in, at the same barycentric coordinates, so the
// result lies exactly on the input surface.
PointMatrix restore_on_input(const ConformingDelaunay& c, const PointMatrix& perturbed, const PointMatrix& V,
                             const SimplexMatrix& F) {
  PointMatrix out = c.points;
  const Index n = static_cast<Index>(V.rows());
  const int d = static_cast<int>(V.cols());
  out.topRows(n) = V;
  std::vector<bool> done(out.rows(), false);
  for (Index r = 0; r < c.constraints.rows(); ++r) {
    const Index parent = c.constraint_parent(r);
    for (int k = 0; k < d; ++k) {
      const Index p = c.constraints(r, k);
      if (p < n || done[p]) continue;
      done[p] = true;
      // Barycentric coordinates in the perturbed parent (least squares in its plane).
      Eigen::MatrixXd edges(d, d - 1);
      for (int j = 1; j < d; ++j) edges.col(j - 1) = (perturbed.row(F(parent, j)) - perturbed.row(F(parent, 0))).transpose();
      const Eigen::VectorXd w = edges.colPivHouseholderQr().solve((c.points.row(p) - perturbed.row(F(parent, 0))).transpose());
      Eigen::RowVectorXd restored = V.row(F(parent, 0));
      for (int j = 1; j < d; ++j) restored += w(j - 1) * (V.row(F(parent, j)) - V.row(F(parent, 0)));
      out.row(p) = restored;
    }
  }
  return out;
}

// Is `apex` strictly on the outer side of the outward constraint face `face`
// (n vertices), within the constraint plane (the first n coordinates)?
// Decided with CGAL's exact predicate.
bool on_outer_side(const PointMatrix& P, const Index* face, int n, Index apex) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  if (n == 3) {
    auto at = [&](Index v) { return K::Point_3(P(v, 0), P(v, 1), P(v, 2)); };
    // orientation(a, b, c, s) is the sign of (s - a) . ((b - a) x (c - a)): positive on the outward side.
    return CGAL::orientation(at(face[0]), at(face[1]), at(face[2]), at(apex)) == CGAL::POSITIVE;
  }
  auto at = [&](Index v) { return K::Point_2(P(v, 0), P(v, 1)); };
  return CGAL::orientation(at(face[0]), at(face[1]), at(apex)) == CGAL::RIGHT_TURN;  // right of a counter-clockwise edge
}

}  // namespace

std::vector<bool> outside_of_constraint(const PointMatrix& P, const SimplexMatrix& A, Index first, Index last,
                                        const SimplexMatrix& constraint, const PointMatrix* exact) {
  const int D = static_cast<int>(P.cols());  // fill dimension, n + 1
  const int n = D - 1;
  auto in_plane = [&](Index v) { return v >= first && v < last; };

  // Projections (Figure 8.5): the face of each simplex spanned by its vertices in the plane.
  std::vector<Key> projection(A.rows());
  std::vector<int> projection_size(A.rows());
  std::unordered_map<Key, Index, KeyHash> cell_of;  // in-plane full simplices (n-simplices of the plane)
  std::vector<Key> cells;
  for (Index s = 0; s < A.rows(); ++s) {
    Index ids[5];
    int count = 0;
    for (int c = 0; c < D + 1; ++c)
      if (in_plane(A(s, c))) ids[count++] = A(s, c);
    projection[s] = make_key(ids, count);
    projection_size[s] = count;
    if (count == n + 1 && !cell_of.count(projection[s])) {
      cell_of.emplace(projection[s], static_cast<Index>(cells.size()));
      cells.push_back(projection[s]);
    }
  }

  // Cell adjacency across their facets, and which facets are constraints.
  std::unordered_map<Key, std::array<Index, 2>, KeyHash> cells_of_facet;
  for (Index c = 0; c < static_cast<Index>(cells.size()); ++c)
    for (int drop = 0; drop < n + 1; ++drop) {
      Index ids[4];
      for (int i = 0, j = 0; i < n + 1; ++i)
        if (i != drop) ids[j++] = cells[c][i];
      auto [it, inserted] = cells_of_facet.try_emplace(make_key(ids, n), std::array<Index, 2>{c, -1});
      if (!inserted) it->second[1] = c;
    }
  std::unordered_map<Key, Index, KeyHash> constraint_face;
  for (Index f = 0; f < constraint.rows(); ++f) constraint_face.emplace(make_key(constraint.row(f).data(), n), f);

  // Grow the outside from the outer side of every constraint face (§8.5.2):
  // the front never crosses a constraint face, so it fills exactly the part
  // of the plane's triangulation outside the shape.
  // Flat cells (coplanar corners, such as the two diagonals of a planar quad
  // of the input) lie on the surface, neither inside nor outside; which side
  // the perturbation tipped them to is noise. They are never stripped:
  // stripping one would leave a crack of zero width in every frame.
  std::vector<bool> flat(cells.size(), false);
  if (exact) {
    for (Index c = 0; c < static_cast<Index>(cells.size()); ++c) {
      Eigen::MatrixXd edges(n, n);
      double longest = 0;
      for (int i = 0; i < n; ++i) {
        edges.row(i) = exact->row(cells[c][i + 1]).head(n) - exact->row(cells[c][0]).head(n);
        longest = std::max(longest, edges.row(i).norm());
      }
      flat[c] = std::abs(edges.determinant()) <= 1e-6 * std::pow(longest, n);
    }
  }
  std::vector<bool> cell_outside(cells.size(), false);
  std::deque<Index> front;
  for (Index f = 0; f < constraint.rows(); ++f) {
    const auto it = cells_of_facet.find(make_key(constraint.row(f).data(), n));
    if (it == cells_of_facet.end())
      fail<std::runtime_error>("constraint face ", f, " is not a face of the fill (Theorem 5.2.1 does not hold)");
    for (const Index c : it->second) {
      if (c < 0 || cell_outside[c]) continue;
      Index apex = -1;
      for (int i = 0; i < n + 1; ++i)
        if (std::find(constraint.row(f).data(), constraint.row(f).data() + n, cells[c][i]) ==
            constraint.row(f).data() + n)
          apex = cells[c][i];
      if (!flat[c] && on_outer_side(P, constraint.row(f).data(), n, apex)) cell_outside[c] = true, front.push_back(c);
    }
  }
  while (!front.empty()) {
    const Index c = front.front();
    front.pop_front();
    for (int drop = 0; drop < n + 1; ++drop) {
      Index ids[4];
      for (int i = 0, j = 0; i < n + 1; ++i)
        if (i != drop) ids[j++] = cells[c][i];
      const Key facet = make_key(ids, n);
      if (constraint_face.count(facet)) continue;
      for (const Index other : cells_of_facet.at(facet))
        if (other >= 0 && !cell_outside[other] && !flat[other]) cell_outside[other] = true, front.push_back(other);
    }
  }

  // Lower-dimensional projections are outside when every cell around them is.
  std::unordered_map<Index, std::vector<Index>> cells_at_vertex;
  for (Index c = 0; c < static_cast<Index>(cells.size()); ++c)
    for (int i = 0; i < n + 1; ++i) cells_at_vertex[cells[c][i]].push_back(c);
  std::vector<bool> outside(A.rows(), false);
  for (Index s = 0; s < A.rows(); ++s) {
    const int count = projection_size[s];
    if (count == 0) continue;  // the simplex does not touch this plane
    if (count == n + 2) {      // flat in the plane: adds nothing (§8.5.1)
      outside[s] = true;
      continue;
    }
    if (count == n + 1) {
      outside[s] = cell_outside[cell_of.at(projection[s])];
      continue;
    }
    bool any = false, all_outside = true;
    for (const Index c : cells_at_vertex[projection[s][0]]) {
      bool contains = true;
      for (int i = 1; i < count && contains; ++i)
        contains = std::find(cells[c].begin(), cells[c].begin() + n + 1, projection[s][i]) != cells[c].begin() + n + 1;
      if (!contains) continue;
      any = true;
      all_outside = all_outside && cell_outside[c];
    }
    outside[s] = any && all_outside;
  }
  return outside;
}

Morph morph(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT, const SimplexMatrix& FT,
            const MorphOptions& options) {
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

  check_closed_shape(VS, FS, "source");
  check_closed_shape(VT, FT, "target");
  if (VS.cols() != VT.cols()) fail<InputError>("source and target must both be 2D or both 3D");
  // TetGen is not told, and may crash on, a surface that intersects itself.
  if (VS.cols() == 3 && intersects_itself(VS, FS)) fail<InputError>("the source intersects itself");
  if (VT.cols() == 3 && intersects_itself(VT, FT)) fail<InputError>("the target intersects itself");
  if (!(options.t1 > options.t0)) fail<InputError>("the morph must run forward in time: t1 (", options.t1, ") <= t0 (", options.t0, ")");
  if (options.method != "strip") fail<InputError>("unknown morph method '", options.method, "'");
  const int d = static_cast<int>(VS.cols());

  // Inputs in general position. Cospherical points (a cube's square faces, a
  // regular torus) make the Delaunay fill ambiguous and Qhull merges such
  // facets into flat simplices, so the fill could miss faces of the
  // conforming surfaces. The combinatorics are therefore computed on points
  // perturbed by a small fraction of the size (1e-7, then larger until the
  // fill is proper and conforms); the result gets the exact coordinates back
  // (restore_on_input), so the perturbation never shows. The planes t0 and t1
  // stay exactly flat (Qhull's own joggle would tilt them, and the part of
  // the fill in each plane would then no longer be one triangulation).
  const double size = std::max((VS.colwise().maxCoeff() - VS.colwise().minCoeff()).norm(),
                               (VT.colwise().maxCoeff() - VT.colwise().minCoeff()).norm());
  PointMatrix VS_perturbed, VT_perturbed, P;
  ConformingDelaunay S, T;
  DelaunayTriangulation fill;
  SimplexMatrix target_constraints;
  Index nS = 0, nT = 0;
  double conform_seconds = 0;
  for (double scale : {1e-7, 1e-6, 1e-5}) {
    std::mt19937_64 rng(20261122);
    std::uniform_real_distribution<double> jitter(-scale * size, scale * size);
    auto perturbed = [&](const PointMatrix& V) {
      PointMatrix out = V;
      for (Index r = 0; r < out.rows(); ++r)
        for (int c = 0; c < d; ++c) out(r, c) += jitter(rng);
      return out;
    };
    const auto conform_start = Clock::now();
    VS_perturbed = perturbed(VS);
    VT_perturbed = perturbed(VT);
    S = conform(VS_perturbed, FS);
    T = conform(VT_perturbed, FT);
    conform_seconds += std::chrono::duration<double>(Clock::now() - conform_start).count();
    if (scale == 1e-7 && options.progress && !options.progress("conforming", 0.3)) throw Cancelled();
    nS = static_cast<Index>(S.points.rows()), nT = static_cast<Index>(T.points.rows());
    P.resize(nS + nT, d + 1);
    P.topLeftCorner(nS, d) = S.points;
    P.topRightCorner(nS, 1).setConstant(options.t0);
    P.bottomLeftCorner(nT, d) = T.points;
    P.bottomRightCorner(nT, 1).setConstant(options.t1);
    fill = delaunay(P);
    target_constraints = T.constraints.array() + nS;
    report.perturbation = scale;
    // Flat simplices within one input's plane are harmless (stripping drops
    // them anyway); flat ones across the planes would leave holes.
    report.flat_fill_simplices = 0;
    for (Index f = 0; f < fill.flat.rows(); ++f) {
      int in_source = 0;
      for (int c = 0; c < d + 2; ++c) in_source += fill.flat(f, c) < nS;
      if (in_source != 0 && in_source != d + 2) ++report.flat_fill_simplices;
    }
    report.missing_source_faces = static_cast<Index>(missing_facets(fill.simplices, S.constraints).size());
    report.missing_target_faces = static_cast<Index>(missing_facets(fill.simplices, target_constraints).size());
    if (report.flat_fill_simplices == 0 && report.missing_source_faces == 0 && report.missing_target_faces == 0) break;
  }
  report.source_conforming = S.is_delaunay;
  report.target_conforming = T.is_delaunay;
  report.fill_simplices = static_cast<Index>(fill.simplices.rows());
  stage("fill", 0.6);
  // Report conforming and filling apart (they alternate in the retries above).
  report.stage_seconds.back().second -= conform_seconds;
  report.stage_seconds.insert(report.stage_seconds.end() - 1, {"conforming", conform_seconds});
  if (report.missing_source_faces || report.missing_target_faces || report.flat_fill_simplices)
    fail<std::runtime_error>("the fill does not conform to the inputs (Theorem 5.2.1): ", report.missing_source_faces,
                             " source and ", report.missing_target_faces, " target faces are missing and ",
                             report.flat_fill_simplices, " simplices are flat",
                             S.is_delaunay && T.is_delaunay ? "" : " (the mesher returned a constrained, not conforming, result)");

  // Sidedness is decided on the perturbed points, the geometry the fill was
  // built on: on the exact input, nearly planar quads (rounded coordinates)
  // would put apexes on either side at random, against the fill's own
  // combinatorics. Then the exact coordinates come back: input vertices as
  // given, added points on their input faces.
  PointMatrix exact = P;
  exact.topLeftCorner(nS, d) = restore_on_input(S, VS_perturbed, VS, FS);
  exact.bottomLeftCorner(nT, d) = restore_on_input(T, VT_perturbed, VT, FT);
  const std::vector<bool> out_s = outside_of_constraint(P, fill.simplices, 0, nS, S.constraints, &exact);
  const std::vector<bool> out_t = outside_of_constraint(P, fill.simplices, nS, nS + nT, target_constraints, &exact);
  P = exact;
  std::vector<Index> kept;
  for (Index s = 0; s < fill.simplices.rows(); ++s)
    if (!out_s[s] && !out_t[s]) kept.push_back(s);
  report.stripped_simplices = report.fill_simplices - static_cast<Index>(kept.size());
  SimplexMatrix A(static_cast<Index>(kept.size()), d + 2);
  for (size_t r = 0; r < kept.size(); ++r) A.row(static_cast<Index>(r)) = fill.simplices.row(kept[r]);
  stage("strip", 0.8);

  const Eigen::VectorXd volumes = signed_volumes(P, A);
  report.min_volume = volumes.size() ? volumes.minCoeff() : 0.0;
  const double volume_tolerance = 1e-8 * std::pow(size, d + 1);
  for (Index s = 0; s < volumes.size(); ++s) {
    if (volumes(s) < -volume_tolerance) ++report.inverted_simplices;
    else if (volumes(s) <= volume_tolerance) ++report.degenerate_simplices;
  }

  // The animation manifold: the boundary of what remains, less the caps.
  const SimplexMatrix B = boundary_facets(A);
  std::vector<Index> lateral;
  for (Index f = 0; f < B.rows(); ++f) {
    bool all_start = true, all_end = true;
    for (int c = 0; c < d + 1; ++c) all_start = all_start && B(f, c) < nS, all_end = all_end && B(f, c) >= nS;
    if (!all_start && !all_end) lateral.push_back(f);
  }
  result.manifold.V = P;
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

  // Validity 2: the slices at t0 and t1 are the inputs, both ways: every
  // slice vertex and face centre on the input, every input vertex and face
  // centre on the slice (face centres catch extra faces whose corners all lie
  // on the input, such as a triangle across its inside).
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
  const Slice start = slice(result.manifold, d, options.t0), end = slice(result.manifold, d, options.t1);
  report.source_distance = two_sided(start, VS, FS);
  report.target_distance = two_sided(end, VT, FT);
  report.ends_reproduced = report.source_distance <= 1e-9 && report.target_distance <= 1e-9;
  stage("validity", 1.0);
  return result;
}

}  // namespace animanifold
