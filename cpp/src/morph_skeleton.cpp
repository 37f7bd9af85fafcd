// The skeleton method of morphing (§8.6): skeleton points, the conforming
// fills with free points, and the classification of each plane (see
// morph_skeleton.hpp; splits in morph_split.cpp, the push in morph_layers.cpp).
#include "morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"
#include "animanifold/morph.hpp"
#include "animanifold/perturbation.hpp"
#include "animanifold/skeleton.hpp"
#include "animanifold/surface_distance.hpp"
#include "simplex_key.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Dense>
#include <array>
#include <set>
#include <numeric>
#include <map>
#include <functional>
#include <limits>
#include <string>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace animanifold {

namespace {

ConformingDelaunay conform(const PointMatrix& V, const SimplexMatrix& F, const std::function<void()>& while_meshing,
                           double time_limit) {
  return V.cols() == 3 ? conforming_delaunay_3d(V, F, while_meshing, time_limit) : conforming_delaunay_2d(V, F);
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

// The convex hull's facets of 3D points as planes: outward unit normal n and
// offset c (n·x = c on the facet, n·x < c inside), one per triangle of CGAL's
// hull (coplanar triangles repeat their plane). Each plane is computed from
// the facet's points, not from the triangle: under bpy CGAL's hull
// triangulates a flat side (a torus's cap) differently from one call to the
// next, and planes through different triangles of it differ in the last
// bits — so did the push's targets (depth_in_hull), and the same morph came
// out different twice in one Blender session.
std::vector<std::pair<Eigen::Vector3d, double>> hull_facet_planes(const PointMatrix& V) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_3> input;  // for the exact coplanarity test below
  for (Index v = 0; v < V.rows(); ++v) input.emplace_back(V(v, 0), V(v, 1), V(v, 2));
  auto point = [&V](Index v) { return Eigen::Vector3d(V(v, 0), V(v, 1), V(v, 2)); };
  // Triangles, then flat sides: triangles across an edge in one plane.
  const std::vector<std::array<Index, 3>> triangles = convex_hull_triangles(V);
  std::vector<Eigen::Vector3d> normals;
  for (const auto& t : triangles) normals.push_back((point(t[1]) - point(t[0])).cross(point(t[2]) - point(t[0])));
  std::vector<Index> side(triangles.size());
  std::iota(side.begin(), side.end(), Index{0});
  std::function<Index(Index)> find = [&](Index x) { return side[x] == x ? x : side[x] = find(side[x]); };
  std::map<std::pair<Index, Index>, Index> by_edge;
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const auto edge = std::minmax(triangles[t][e], triangles[t][(e + 1) % 3]);
      const auto [at, fresh] = by_edge.emplace(edge, static_cast<Index>(t));
      if (fresh) continue;
      const Index u = at->second;
      // Exactly coplanar (the opposite corner in the plane): normals of
      // thin triangles, compared with a tolerance, grouped a flat side one
      // way or another depending on how the hull triangulated it.
      Index opposite = triangles[u][0];
      for (const Index v : triangles[u])
        if (v != edge.first && v != edge.second) opposite = v;
      if (CGAL::coplanar(input[triangles[t][0]], input[triangles[t][1]], input[triangles[t][2]], input[opposite]))
        side[find(static_cast<Index>(t))] = find(u);
    }
  // Each side's plane through three of its points chosen by index: the
  // lowest, the farthest from it, the farthest from the line of those two.
  std::map<Index, std::vector<Index>> triangles_of;  // by side
  for (size_t t = 0; t < triangles.size(); ++t) triangles_of[find(static_cast<Index>(t))].push_back(static_cast<Index>(t));
  std::map<Index, std::pair<Eigen::Vector3d, double>> plane_of;
  for (const auto& [root, members] : triangles_of) {
    std::set<Index> points;
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    for (const Index u : members) points.insert(triangles[u].begin(), triangles[u].end()), outward += normals[u];
    const Index a = *points.begin();
    const Eigen::Vector3d pa = point(a);
    Index b = a, c = a;
    double best = -1;
    for (const Index v : points)
      if ((point(v) - pa).squaredNorm() > best) best = (point(v) - pa).squaredNorm(), b = v;
    const Eigen::Vector3d ab = (point(b) - pa).normalized();
    best = -1;
    for (const Index v : points) {
      const Eigen::Vector3d w = point(v) - pa;
      const double off = (w - w.dot(ab) * ab).squaredNorm();
      if (off > best) best = off, c = v;
    }
    Eigen::Vector3d normal = (point(b) - pa).cross(point(c) - pa).normalized();
    if (normal.dot(outward) < 0) normal = -normal;
    plane_of[root] = {normal, normal.dot(pa)};
  }
  std::vector<std::pair<Eigen::Vector3d, double>> planes;
  for (size_t t = 0; t < triangles.size(); ++t) planes.push_back(plane_of.at(find(static_cast<Index>(t))));
  return planes;
}

}  // namespace

std::vector<std::array<Index, 3>> convex_hull_triangles(const PointMatrix& V) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_3> input;
  for (Index v = 0; v < V.rows(); ++v) input.emplace_back(V(v, 0), V(v, 1), V(v, 2));
  CGAL::Surface_mesh<K::Point_3> hull;
  translating_cgal_failures("taking the convex hull of " + std::to_string(V.rows()) + " points in R^3",
                            [&] { CGAL::convex_hull_3(input.begin(), input.end(), hull); });
  std::map<std::array<double, 3>, Index> index_of;  // the hull's points are V's rows, bit for bit
  for (Index v = V.rows() - 1; v >= 0; --v) index_of[{V(v, 0), V(v, 1), V(v, 2)}] = v;  // the first of duplicates
  std::vector<std::array<Index, 3>> triangles;
  for (const auto f : hull.faces()) {
    std::array<Index, 3> t{};
    int i = 0;
    for (const auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
      const auto& p = hull.point(v);
      t[i++] = index_of.at({p.x(), p.y(), p.z()});
    }
    triangles.push_back(t);
  }
  return triangles;
}

Eigen::VectorXd depth_in_hull(const PointMatrix& points, const PointMatrix& V) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  Eigen::VectorXd depth = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  if (V.cols() == 3) {
    for (const auto& [normal, offset] : hull_facet_planes(V))
      for (Index p = 0; p < points.rows(); ++p)
        depth(p) = std::min(depth(p), offset - normal.dot(Eigen::Vector3d(points.row(p).transpose())));
    return depth;
  }
  std::vector<K::Point_2> input, hull;
  for (Index v = 0; v < V.rows(); ++v) input.emplace_back(V(v, 0), V(v, 1));
  translating_cgal_failures(  // counter-clockwise
      "taking the convex hull of " + std::to_string(V.rows()) + " points in R^2",
      [&] { CGAL::convex_hull_2(input.begin(), input.end(), std::back_inserter(hull)); });
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d a(hull[i].x(), hull[i].y()), b(hull[(i + 1) % hull.size()].x(), hull[(i + 1) % hull.size()].y());
    const Eigen::Vector2d outward = Eigen::Vector2d(b.y() - a.y(), a.x() - b.x()).normalized();
    for (Index p = 0; p < points.rows(); ++p)
      depth(p) = std::min(depth(p), -outward.dot(Eigen::Vector2d(points.row(p).transpose()) - a));
  }
  return depth;
}

std::vector<bool> on_convex_hull(const PointMatrix& points, const PointMatrix& V) {
  std::vector<bool> on(static_cast<size_t>(points.rows()), false);
  if (V.cols() != 3 || points.cols() != 3 || V.rows() < 4) return on;
  const std::vector<std::pair<Eigen::Vector3d, double>> planes = hull_facet_planes(V);
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  for (Index v = 0; v < points.rows(); ++v)
    for (const auto& [n, c] : planes)
      if (std::abs(n.dot(Eigen::Vector3d(points.row(v).transpose())) - c) <= 1e-12 * size) {
        on[v] = true;
        break;
      }
  return on;
}

PointMatrix perturbed_along_hull_faces(const PointMatrix& V, double scale, std::uint64_t salt) {
  PointMatrix out = perturbed_by_position(V, scale, salt);
  // Points on the hull where they are: its corners as well as its flat
  // sides' points (see morph_skeleton.hpp).
  const std::vector<bool> on = on_convex_hull(V, V);
  for (Index v = 0; v < V.rows(); ++v)
    if (on[v]) out.row(v) = V.row(v);
  return out;
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
  const PointMatrix perturbed = perturbed_by_position(V, 1e-6 * size, 31337);  // the same shape, the same skeleton
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
                                    const PointMatrix& K, const std::string& name,
                                    const std::function<void()>& while_meshing, double mesher_time_limit) {
  const int d = static_cast<int>(V.cols());
  PointMatrix points(V.rows() + K.rows(), d);
  points << V, K;
  ConformingInput result;
  result.fill = conform(points, F, while_meshing, mesher_time_limit);
  if (!result.fill.is_delaunay)
    fail<MeshingError>("the mesher returned a constrained, not conforming, Delaunay fill of the ", name, ": ",
                             result.fill.non_delaunay_faces, " of its ", result.fill.constraints.rows(),
                             " refined faces are not Delaunay faces",
                             d == 3 ? " after " + std::to_string(result.fill.mending_rounds) + " rounds of mending" : "");
  result.exact_points = restore_on_input(result.fill, V, V_exact, F);
  return result;
}

namespace {
// Relative volume (|det| / longest edge^n) below which a cell of a plane is
// flat at the exact coordinates: rounding only.
constexpr double kFlatCell = 1e-12;
}  // namespace

PlaneCells classify_plane(const PointMatrix& P, const PointMatrix& exact, const SimplexMatrix& A,
                          const std::vector<bool>& in_plane, const SimplexMatrix& constraint, bool convex) {
  const int n = static_cast<int>(P.cols()) - 1;
  using CellKey = SimplexKey<4>;
  const auto key_of = simplex_key<4>;
  PlaneCells plane;
  std::unordered_set<CellKey, SimplexKeyHash> seen;
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

  std::unordered_set<CellKey, SimplexKeyHash> constraint_keys;
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
    // Flat only as far as rounding goes: cells of exactly planar quads (a
    // cube's squares). A float32 input's quads bend by ~1e-8 of the size
    // (Blender's UV sphere, its torus); their cells are real, and marked
    // neither in nor out they stayed in the plane with the quad's other
    // diagonal, so the frame at t0 missed the input by that (5e-8 of the
    // diagonal for the demo's sphere). In or out as the fill decided, the
    // constraint faces alone part the plane, and the end frame is the input.
    if (std::abs(edges.determinant()) > kFlatCell * std::pow(longest, n)) continue;
    int constraint_facets = 0;
    for (int drop = 0; drop <= n; ++drop) {
      Index ids[4];
      for (int i = 0, j = 0; i <= n; ++i)
        if (i != drop) ids[j++] = plane.cells(c, i);
      constraint_facets += static_cast<int>(constraint_keys.count(key_of(ids, n)));
    }
    bool all_on_surface = true;
    for (int i = 0; i <= n; ++i) all_on_surface = all_on_surface && on_surface[plane.cells(c, i)];
    plane.flat[c] = constraint_facets >= 2 || (convex && constraint_facets >= 1 && all_on_surface);
  }
  plane.outside = outside_cells(P, plane.cells, constraint, plane.flat);
  plane.free.assign(P.rows(), false);
  for (Index c = 0; c < plane.cells.rows(); ++c)
    if (plane.outside[c])
      for (int i = 0; i <= n; ++i) plane.free[plane.cells(c, i)] = !on_surface[plane.cells(c, i)];
  return plane;
}

}  // namespace animanifold
