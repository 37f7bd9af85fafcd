#include "animanifold/morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/morph.hpp"
#include "animanifold/skeleton.hpp"
#include "animanifold/surface_distance.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Dense>
#include <array>
#include <limits>
#include <cmath>
#include <random>
#include <unordered_map>
#include <unordered_set>

namespace animanifold {

namespace {

ConformingDelaunay conform(const PointMatrix& V, const SimplexMatrix& F) {
  return V.cols() == 3 ? conforming_delaunay_3d(V, F) : conforming_delaunay_2d(V, F);
}

// Keeps points at least `gap` apart, first come first kept, with a grid of
// cells of size `gap` so that only the 3^d neighbouring cells are compared.
std::vector<Index> spread_out(const PointMatrix& points, double gap) {
  const int d = static_cast<int>(points.cols());
  struct CellHash {
    size_t operator()(const std::array<std::int64_t, 3>& c) const {
      return static_cast<size_t>(c[0] * 73856093 ^ c[1] * 19349663 ^ c[2] * 83492791);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<Index>, CellHash> grid;
  std::vector<Index> kept;
  for (Index p = 0; p < points.rows(); ++p) {
    std::array<std::int64_t, 3> cell{0, 0, 0};
    for (int c = 0; c < d; ++c) cell[c] = static_cast<std::int64_t>(std::floor(points(p, c) / gap));
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx)
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dz = (d == 3 ? -1 : 0); dz <= (d == 3 ? 1 : 0) && !near; ++dz) {
          const auto it = grid.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
          if (it == grid.end()) continue;
          for (const Index q : it->second)
            if ((points.row(q) - points.row(p)).norm() < gap) {
              near = true;
              break;
            }
        }
    if (near) continue;
    grid[cell].push_back(p);
    kept.push_back(p);
  }
  return kept;
}

}  // namespace

Eigen::VectorXd depth_in_hull(const PointMatrix& points, const PointMatrix& V) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  Eigen::VectorXd depth = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  if (V.cols() == 3) {
    std::vector<K::Point_3> input;
    for (Index v = 0; v < V.rows(); ++v) input.emplace_back(V(v, 0), V(v, 1), V(v, 2));
    CGAL::Surface_mesh<K::Point_3> hull;
    CGAL::convex_hull_3(input.begin(), input.end(), hull);
    for (const auto f : hull.faces()) {
      std::array<Eigen::Vector3d, 3> corner;
      int i = 0;
      for (const auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
        const auto& p = hull.point(v);
        corner[i++] = Eigen::Vector3d(p.x(), p.y(), p.z());
      }
      const Eigen::Vector3d normal = (corner[1] - corner[0]).cross(corner[2] - corner[0]).normalized();  // outward
      for (Index p = 0; p < points.rows(); ++p)
        depth(p) = std::min(depth(p), -normal.dot(Eigen::Vector3d(points.row(p).transpose()) - corner[0]));
    }
    return depth;
  }
  std::vector<K::Point_2> input, hull;
  for (Index v = 0; v < V.rows(); ++v) input.emplace_back(V(v, 0), V(v, 1));
  CGAL::convex_hull_2(input.begin(), input.end(), std::back_inserter(hull));  // counter-clockwise
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d a(hull[i].x(), hull[i].y()), b(hull[(i + 1) % hull.size()].x(), hull[(i + 1) % hull.size()].y());
    const Eigen::Vector2d outward = Eigen::Vector2d(b.y() - a.y(), a.x() - b.x()).normalized();
    for (Index p = 0; p < points.rows(); ++p)
      depth(p) = std::min(depth(p), -outward.dot(Eigen::Vector2d(points.row(p).transpose()) - a));
  }
  return depth;
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

PointMatrix external_skeleton_points(const PointMatrix& V, const SimplexMatrix& F, double gap) {
  const int d = static_cast<int>(V.cols());
  SkeletonOptions skeleton_options;
  skeleton_options.internal = false;
  // On a perturbed copy: Qhull's Voronoi diagram of cospherical vertices (a
  // parametric torus: every ring on one circle) merges the degenerate
  // regions, and every bisector then looked as if it crossed the mesh (an
  // empty skeleton). 1e-6 of the size is far below the gap kept below.
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  std::mt19937_64 rng(31337);
  std::uniform_real_distribution<double> jitter(-1e-6 * size, 1e-6 * size);
  PointMatrix perturbed = V;
  for (Index r = 0; r < perturbed.rows(); ++r)
    for (int c = 0; c < d; ++c) perturbed(r, c) += jitter(rng);
  const VoronoiSkeleton skeleton = voronoi_skeleton(perturbed, F, skeleton_options);
  std::vector<bool> used(skeleton.vertices.rows(), false);
  for (Index f = 0; f < skeleton.faces.rows(); ++f)
    for (int c = 0; c < skeleton.faces.cols(); ++c) used[skeleton.faces(f, c)] = true;
  std::vector<Index> candidates;
  for (Index v = 0; v < skeleton.vertices.rows(); ++v)
    if (used[v] && !skeleton.on_mesh(v)) candidates.push_back(v);
  PointMatrix points(static_cast<Index>(candidates.size()), d);
  for (size_t r = 0; r < candidates.size(); ++r) points.row(static_cast<Index>(r)) = skeleton.vertices.row(candidates[r]);
  // Off the surface, and well inside the convex hull: the skeleton is
  // clipped to the hull (§7.4), and the cut points lie in the hull's flat
  // facets together with surface vertices (a torus's top and bottom rings),
  // where their cells are flat and would not let them move at all.
  const Eigen::VectorXd distance = distances_to_surface(points, V, F);
  const Eigen::VectorXd depth = depth_in_hull(points, V);
  PointMatrix off_surface(points.rows(), d);
  Index count = 0;
  for (Index p = 0; p < points.rows(); ++p)
    if (distance(p) >= gap && depth(p) >= std::max(gap, 0.25 * distance(p))) off_surface.row(count++) = points.row(p);
  off_surface.conservativeResize(count, d);
  const std::vector<Index> kept = spread_out(off_surface, gap);
  PointMatrix out(static_cast<Index>(kept.size()), d);
  for (size_t r = 0; r < kept.size(); ++r) out.row(static_cast<Index>(r)) = off_surface.row(kept[r]);
  return out;
}

ConformingInput conform_with_points(const PointMatrix& V, const PointMatrix& V_exact, const SimplexMatrix& F,
                                    const PointMatrix& K) {
  const int d = static_cast<int>(V.cols());
  PointMatrix points(V.rows() + K.rows(), d);
  points << V, K;
  ConformingInput result;
  result.fill = conform(points, F);
  if (!result.fill.is_delaunay)
    fail<std::runtime_error>("the mesher returned a constrained, not conforming, Delaunay fill (",
                             result.fill.non_delaunay_faces, " faces are not Delaunay)");
  result.exact_points = restore_on_input(result.fill, V, V_exact, F);
  return result;
}

PlaneCells classify_plane(const PointMatrix& P, const PointMatrix& exact, const SimplexMatrix& A,
                          const std::vector<bool>& in_plane, const SimplexMatrix& constraint) {
  const int n = static_cast<int>(P.cols()) - 1;
  using CellKey = std::array<Index, 4>;
  struct Hash {
    size_t operator()(const CellKey& k) const {
      size_t h = 1469598103934665603ull;
      for (Index v : k) h = (h ^ static_cast<size_t>(static_cast<std::uint32_t>(v))) * 1099511628211ull;
      return h;
    }
  };
  auto key_of = [&](const Index* ids, int size) {
    CellKey k{-1, -1, -1, -1};
    std::copy(ids, ids + size, k.begin());
    std::sort(k.begin(), k.begin() + size);
    return k;
  };
  PlaneCells plane;
  std::unordered_set<CellKey, Hash> seen;
  std::vector<CellKey> cells;
  for (Index s = 0; s < A.rows(); ++s) {
    Index ids[5];
    int count = 0;
    for (int c = 0; c < n + 2; ++c)
      if (in_plane[A(s, c)]) ids[count++] = A(s, c);
    if (count != n + 1) continue;
    const CellKey key = key_of(ids, count);
    if (seen.insert(key).second) cells.push_back(key);
  }
  plane.cells.resize(static_cast<Index>(cells.size()), n + 1);
  for (Index c = 0; c < plane.cells.rows(); ++c)
    for (int i = 0; i <= n; ++i) plane.cells(c, i) = cells[c][i];

  std::unordered_set<CellKey, Hash> constraint_keys;
  std::vector<bool> on_surface(P.rows(), false);
  for (Index f = 0; f < constraint.rows(); ++f) {
    constraint_keys.insert(key_of(constraint.row(f).data(), n));
    for (int c = 0; c < n; ++c) on_surface[constraint(f, c)] = true;
  }
  plane.flat.assign(cells.size(), false);
  Eigen::MatrixXd edges(n, n);
  for (Index c = 0; c < plane.cells.rows(); ++c) {
    double longest = 0;
    for (int i = 0; i < n; ++i) {
      edges.row(i) = exact.row(plane.cells(c, i + 1)).head(n) - exact.row(plane.cells(c, 0)).head(n);
      longest = std::max(longest, edges.row(i).norm());
    }
    if (std::abs(edges.determinant()) > 1e-6 * std::pow(longest, n)) continue;
    int constraint_facets = 0;
    for (int drop = 0; drop <= n; ++drop) {
      Index ids[4];
      for (int i = 0, j = 0; i <= n; ++i)
        if (i != drop) ids[j++] = plane.cells(c, i);
      constraint_facets += static_cast<int>(constraint_keys.count(key_of(ids, n)));
    }
    plane.flat[c] = constraint_facets >= 2;
  }
  plane.outside = outside_cells(P, plane.cells, constraint, plane.flat);
  plane.free.assign(P.rows(), false);
  for (Index c = 0; c < plane.cells.rows(); ++c)
    if (plane.outside[c])
      for (int i = 0; i <= n; ++i) plane.free[plane.cells(c, i)] = !on_surface[plane.cells(c, i)];
  return plane;
}

std::vector<std::vector<Index>> uncovered_outside_faces(const PlaneCells& shape) {
  const SimplexMatrix& cells = shape.cells;
  const int corners = static_cast<int>(cells.cols());  // n + 1
  using FaceKey = std::array<Index, 4>;
  struct Hash {
    size_t operator()(const FaceKey& k) const {
      size_t h = 1469598103934665603ull;
      for (Index v : k) h = (h ^ static_cast<size_t>(static_cast<std::uint32_t>(v))) * 1099511628211ull;
      return h;
    }
  };
  auto key_of = [&](Index c, unsigned mask) {
    FaceKey k{-1, -1, -1, -1};
    int j = 0;
    for (int i = 0; i < corners; ++i)
      if (mask & (1u << i)) k[j++] = cells(c, i);
    std::sort(k.begin(), k.begin() + j);
    return k;
  };
  auto size_of = [](unsigned mask) { return __builtin_popcount(mask); };
  // Faces of cells that are not outside (inside the shape, or flat on its
  // surface) lie inside or on the shape.
  std::unordered_set<FaceKey, Hash> covered, listed;
  for (Index c = 0; c < cells.rows(); ++c)
    if (!shape.outside[c] || shape.flat[c])
      for (unsigned mask = 1; mask < (1u << corners); ++mask)
        if (size_of(mask) >= 2) covered.insert(key_of(c, mask));
  std::vector<std::vector<Index>> faces;
  for (int size = 2; size <= corners; ++size)
    for (Index c = 0; c < cells.rows(); ++c) {
      if (!shape.outside[c] || shape.flat[c]) continue;
      bool has_free = false;
      for (int i = 0; i < corners; ++i) has_free = has_free || shape.free[cells(c, i)];
      if (has_free) continue;
      for (unsigned mask = 1; mask < (1u << corners); ++mask) {
        if (size_of(mask) != size) continue;
        const FaceKey key = key_of(c, mask);
        if (covered.count(key) || listed.count(key)) continue;
        bool split_below = false;  // one of its own faces is listed: it gets a free vertex from that split
        for (unsigned sub = (mask - 1) & mask; sub && !split_below; sub = (sub - 1) & mask)
          split_below = size_of(sub) >= 2 && listed.count(key_of(c, sub));
        if (split_below) continue;
        listed.insert(key);
        faces.emplace_back(key.begin(), key.begin() + size);
      }
    }
  return faces;
}

IndexVector split_faces(PointMatrix& P, SimplexMatrix& A, const std::vector<std::vector<Index>>& faces) {
  const int D = static_cast<int>(P.cols());
  IndexVector added(static_cast<Index>(faces.size()));
  if (faces.empty()) return added;
  // Which simplices hold each vertex, kept up to date through the splits.
  std::vector<std::vector<Index>> at_vertex(P.rows());
  for (Index s = 0; s < A.rows(); ++s)
    for (int c = 0; c <= D; ++c) at_vertex[A(s, c)].push_back(s);
  std::vector<Eigen::Matrix<Index, 1, Eigen::Dynamic>> appended;  // simplices past A's rows
  auto row_of = [&](Index s) -> Eigen::Matrix<Index, 1, Eigen::Dynamic> {
    return s < A.rows() ? Eigen::Matrix<Index, 1, Eigen::Dynamic>(A.row(s)) : appended[s - A.rows()];
  };
  auto set_row = [&](Index s, const Eigen::Matrix<Index, 1, Eigen::Dynamic>& row) {
    if (s < A.rows()) A.row(s) = row;
    else appended[s - A.rows()] = row;
  };
  std::vector<Eigen::RowVectorXd> new_points;
  // Not the centroid itself but a point near it, at random weights between
  // 1 and 2: on symmetric inputs (a shape and its mirror image) centroids of
  // chords line up with the input's own faces, and the cells they make are
  // slivers that hold the point at the plane when it is pushed.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> weight(1.0, 2.0);
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::vector<Index>& face = faces[f];
    const Index m = static_cast<Index>(P.rows() + new_points.size());
    Eigen::RowVectorXd point = Eigen::RowVectorXd::Zero(D);
    double total = 0;
    for (const Index v : face) {
      const double w = weight(rng);
      point += w * P.row(v);
      total += w;
    }
    new_points.push_back(point / total);
    at_vertex.emplace_back();
    added(static_cast<Index>(f)) = m;
    // The star of the face: simplices holding all its vertices.
    std::vector<Index> star;
    for (const Index s : at_vertex[face[0]]) {
      const auto row = row_of(s);
      bool holds = true;
      for (size_t i = 1; i < face.size() && holds; ++i)
        holds = std::find(row.data(), row.data() + D + 1, face[i]) != row.data() + D + 1;
      if (holds) star.push_back(s);
    }
    if (star.empty()) fail<std::runtime_error>("face ", f, " to split is not a face of the fill");
    for (const Index s : star) {
      const auto original = row_of(s);
      // Replacing a corner of a positive simplex by a point of a face that
      // holds the corner keeps it positive: the volume scales by the point's
      // barycentric weight at that corner.
      for (size_t i = 0; i < face.size(); ++i) {
        auto row = original;
        const int corner = static_cast<int>(std::find(row.data(), row.data() + D + 1, face[i]) - row.data());
        row(corner) = m;
        Index target = s;
        if (i > 0) {
          target = static_cast<Index>(A.rows() + appended.size());
          appended.push_back(row);
        } else {
          set_row(s, row);
        }
        for (int c = 0; c <= D; ++c)
          if (i > 0 || row(c) == m) at_vertex[row(c)].push_back(target);
      }
      // The first replaced corner no longer holds s.
      auto& list = at_vertex[face[0]];
      list.erase(std::find(list.begin(), list.end(), s));
    }
  }
  const Index old_points = static_cast<Index>(P.rows()), old_simplices = static_cast<Index>(A.rows());
  P.conservativeResize(old_points + static_cast<Index>(new_points.size()), D);
  for (size_t p = 0; p < new_points.size(); ++p) P.row(old_points + static_cast<Index>(p)) = new_points[p];
  A.conservativeResize(old_simplices + static_cast<Index>(appended.size()), D + 1);
  for (size_t s = 0; s < appended.size(); ++s) A.row(old_simplices + static_cast<Index>(s)) = appended[s];
  return added;
}

namespace {

// What the push must keep positive: a simplex of the fill (D+1 corners), or
// a boundary facet of it (D corners) measured within its own hyperplane —
// its normal as the last row of the matrix — times the facet's sign then.
// Where the fill's boundary is flat across both planes (two tori with their
// bottoms at the same height make a facet of the 4D hull in z = -0.35), the
// simplices behind it are slivers of the perturbation whose sign says
// nothing; the facets themselves could then fold within the hyperplane, and
// the frames would overlap themselves there.
struct PushConstraint {
  std::array<Index, 5> corners{-1, -1, -1, -1, -1};
  int count = 0;
  Eigen::VectorXd normal;  // facets only
  double sign = 1.0;
};

// (value, rate) of a constraint's determinant under moves of its corners
// along the last axis by `share(v)` per unit of the move parameter.
template <class Share>
std::pair<double, double> affine_volume(const PointMatrix& P, const PushConstraint& k, const Share& share,
                                        Eigen::MatrixXd& m) {
  const int D = static_cast<int>(P.cols());
  for (int c = 1; c < k.count; ++c) m.row(c - 1) = P.row(k.corners[c]) - P.row(k.corners[0]);
  if (k.count == D) m.row(D - 1) = k.normal.transpose();
  const double before = k.sign * m.determinant();
  for (int c = 1; c < k.count; ++c) m(c - 1, D - 1) = share(k.corners[c]) - share(k.corners[0]);
  if (k.count == D) m(D - 1, D - 1) = 0.0;
  return {before, k.sign * m.determinant()};
}

}  // namespace

PushReport push_free_vertices(PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& moved, double direction,
                              const Eigen::VectorXd& target, double safety, int sweeps) {
  const int D = static_cast<int>(P.cols());
  if (A.cols() != D + 1) fail<InputError>("pushing needs ", D, "-simplices in R^", D, ", got ", A.cols(), " corners");
  PushReport report;
  std::vector<PushConstraint> constraints;
  auto touches = [&](const Index* ids, int count) {
    for (int c = 0; c < count; ++c)
      if (moved[ids[c]]) return true;
    return false;
  };
  for (Index s = 0; s < A.rows(); ++s)
    if (touches(A.row(s).data(), D + 1)) {
      PushConstraint k;
      std::copy(A.row(s).data(), A.row(s).data() + D + 1, k.corners.begin());
      k.count = D + 1;
      constraints.push_back(k);
    }
  const SimplexMatrix boundary = boundary_facets(A);
  const double size = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  Eigen::MatrixXd basis(D - 1, D), m(D, D);
  for (Index f = 0; f < boundary.rows(); ++f) {
    if (!touches(boundary.row(f).data(), D)) continue;
    for (int c = 1; c < D; ++c) basis.row(c - 1) = P.row(boundary(f, c)) - P.row(boundary(f, 0));
    Eigen::FullPivLU<Eigen::MatrixXd> lu(basis);
    if (lu.dimensionOfKernel() != 1) continue;
    PushConstraint k;
    std::copy(boundary.row(f).data(), boundary.row(f).data() + D, k.corners.begin());
    k.count = D;
    k.normal = lu.kernel().col(0).normalized();
    const double measure = affine_volume(P, k, [](Index) { return 0.0; }, m).first;
    if (std::abs(measure) <= 1e-9 * std::pow(size, D - 1)) continue;  // flat already: nothing to keep
    k.sign = measure > 0 ? 1.0 : -1.0;
    constraints.push_back(k);
  }
  std::vector<std::vector<Index>> star(P.rows());
  for (size_t i = 0; i < constraints.size(); ++i)
    for (int c = 0; c < constraints[i].count; ++c)
      if (moved[constraints[i].corners[c]]) star[constraints[i].corners[c]].push_back(static_cast<Index>(i));
  std::vector<double> travelled(P.rows(), 0.0);
  // How far v may go before a constraint of its star goes flat, the others
  // where they are now: value(δ) = before + δ·rate (v's last coordinate sits
  // in the last column only, and the determinant is linear in that column).
  auto limit_of = [&](Index v, bool count_degenerate) {
    double limit = std::numeric_limits<double>::infinity();
    for (const Index i : star[v]) {
      const auto [before, rate] = affine_volume(P, constraints[i], [&](Index w) { return w == v ? direction : 0.0; }, m);
      if (!(before > 0)) {
        report.degenerate += count_degenerate;
        continue;
      }
      if (rate < 0) limit = std::min(limit, -before / rate);
    }
    return limit;
  };
  // First all free vertices together: each moves by its share of one
  // common parameter Δ (target(v)/largest·Δ). Every constraint is then
  // affine in Δ too (its moved corners' last coordinates are affine in Δ,
  // all in one column), so the largest safe Δ is exact. Together, free
  // vertices that share a sliver move as one and do not flatten it, which
  // a vertex moved alone would at once (a chord's point and the faces it
  // lines up with on symmetric inputs). Vertices of the constraints that
  // stop the common move are frozen where they are, and the others go on.
  const double largest = target.size() ? target.maxCoeff() : 0.0;
  std::vector<bool> active(P.rows(), false);
  for (Index v = 0; v < P.rows(); ++v) active[v] = moved[v] && target(v) > 0;
  double done = 0;
  for (int round = 0; round < 64 && largest > 0 && done < largest; ++round) {
    std::vector<double> limit(constraints.size(), std::numeric_limits<double>::infinity());
    double smallest = std::numeric_limits<double>::infinity();
    auto share = [&](Index v) { return active[v] ? direction * target(v) / largest : 0.0; };
    for (size_t i = 0; i < constraints.size(); ++i) {
      const PushConstraint& k = constraints[i];
      bool any = false;
      for (int c = 0; c < k.count; ++c) any = any || active[k.corners[c]];
      if (!any) continue;
      const auto [before, rate] = affine_volume(P, k, share, m);
      if (before > 0 && rate < 0) smallest = std::min(smallest, limit[i] = -before / rate);
    }
    const double remaining = largest - done;
    const double step = std::min(remaining, safety * smallest);
    for (Index v = 0; v < P.rows(); ++v)
      if (active[v]) {
        P(v, D - 1) += direction * target(v) / largest * step;
        travelled[v] += target(v) / largest * step;
      }
    done += step;
    if (step >= remaining) break;
    // Freeze the corners of the constraints that would stop the next steps soon.
    for (size_t i = 0; i < constraints.size(); ++i)
      if (limit[i] - step <= 2 * (smallest - step))
        for (int c = 0; c < constraints[i].count; ++c) active[constraints[i].corners[c]] = false;
  }
  // Then each frozen vertex alone, as far as its own constraints allow.
  const int levels = std::max(1, sweeps) * 4;
  for (int level = 1; level <= levels + 2; ++level) {
    for (Index v = 0; v < P.rows(); ++v) {
      const double height = moved[v] ? target(v) * std::min(level, levels) / levels : 0.0;
      if (!moved[v] || travelled[v] >= height) continue;
      const double step = std::min(height - travelled[v], safety * limit_of(v, level == 1));
      if (!(step > 0)) continue;
      P(v, D - 1) += direction * step;
      travelled[v] += step;
    }
  }
  double sum = 0;
  report.smallest = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < P.rows(); ++v) {
    if (!moved[v]) continue;
    ++report.vertices;
    report.held_back += travelled[v] < 0.1 * target(v);
    sum += travelled[v];
    report.smallest = std::min(report.smallest, travelled[v]);
    report.largest = std::max(report.largest, travelled[v]);
  }
  if (report.vertices == 0) report.smallest = 0;
  report.mean = report.vertices ? sum / report.vertices : 0.0;
  return report;
}

}  // namespace animanifold
