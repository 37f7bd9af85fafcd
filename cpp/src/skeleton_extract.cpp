// Voronoi skeleton extraction (§7.3, §7.4) and attachment (§8.6.2): the
// bisector polygons b_ij of the Voronoi diagram of a separable mesh's
// vertices that do not intersect the mesh, classified internal/external and
// clipped to the convex hull. Mesh queries use CGAL's AABB tree with exact
// predicates (Epick).
#include "animanifold/errors.hpp"
#include "animanifold/skeleton.hpp"
#include "cgal_failures.hpp"
#include "skeleton_internal.hpp"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <chrono>
#include <iterator>
#include <map>
#include <memory>
#include <unordered_map>

namespace animanifold {

using namespace skeleton_detail;

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using Segment = K::Segment_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using SegmentIterator = std::vector<Segment>::const_iterator;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, TriangleIterator>>>;
using SegmentTree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, SegmentIterator>>>;

Point to_point(const Vec3& p) { return Point(p[0], p[1], p[2]); }
Vec3 to_vec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The mesh as an AABB tree, with angle-weighted pseudonormals for the sign of
// the distance (Bærentzen & Aanæs): x is inside when (x - c)·n < 0 for the
// closest point c and the pseudonormal n of the feature c lies on.
class MeshQuery {
 public:
  MeshQuery(const std::vector<Vec3>& P, const SimplexMatrix& F) : P_(P), F_(F), D_(static_cast<int>(F.cols())) {
    first_face_.assign(P.size(), 0);
    for (Index f = F.rows() - 1; f >= 0; --f)
      for (int k = 0; k < D_; ++k) first_face_[F(f, k)] = f;
    if (D_ == 3) {
      for (Index f = 0; f < F.rows(); ++f)
        triangles_.emplace_back(to_point(P[F(f, 0)]), to_point(P[F(f, 1)]), to_point(P[F(f, 2)]));
      triangle_tree_ = std::make_unique<TriangleTree>(triangles_.begin(), triangles_.end());
      triangle_tree_->build();  // now, so that CGAL's failures surface where mesh_query translates them
      edges_ = edge_table(F);
      face_normal_.resize(static_cast<size_t>(F.rows()));
      vertex_normal_.assign(P.size(), Vec3::Zero());
      edge_normal_.assign(edges_.edge.size(), Vec3::Zero());
      for (Index f = 0; f < F.rows(); ++f) {
        const Vec3 &a = P[F(f, 0)], &b = P[F(f, 1)], &c = P[F(f, 2)];
        face_normal_[f] = (b - a).cross(c - a).normalized();
        for (int k = 0; k < 3; ++k) {
          const Vec3 &o = P[F(f, k)], &u = P[F(f, (k + 1) % 3)], &w = P[F(f, (k + 2) % 3)];
          const double angle = std::acos(std::clamp((u - o).normalized().dot((w - o).normalized()), -1.0, 1.0));
          vertex_normal_[F(f, k)] += angle * face_normal_[f];
          edge_normal_[edges_.face_edges[f][k]] += face_normal_[f];
        }
      }
    } else {
      for (Index s = 0; s < F.rows(); ++s) segments_.emplace_back(to_point(P[F(s, 0)]), to_point(P[F(s, 1)]));
      segment_tree_ = std::make_unique<SegmentTree>(segments_.begin(), segments_.end());
      segment_tree_->build();
      face_normal_.resize(static_cast<size_t>(F.rows()));
      vertex_normal_.assign(P.size(), Vec3::Zero());
      for (Index s = 0; s < F.rows(); ++s) {
        const Vec3 d = P[F(s, 1)] - P[F(s, 0)];
        face_normal_[s] = Vec3(d[1], -d[0], 0).normalized();  // outward for counter-clockwise polygons
        vertex_normal_[F(s, 0)] += face_normal_[s];
        vertex_normal_[F(s, 1)] += face_normal_[s];
      }
    }
  }

  // Signed distance: negative inside. `near` is a mesh vertex close to x
  // (a Voronoi vertex's site): the search starts from it.
  double signed_distance(const Vec3& x, Index near) const {
    const Point q = to_point(x);
    Vec3 c, n;
    if (D_ == 3) {
      const auto [cp, it] = triangle_tree_->closest_point_and_primitive(
          q, {to_point(P_[near]), triangles_.begin() + first_face_[near]});
      const Index f = static_cast<Index>(it - triangles_.begin());
      c = to_vec(cp);
      const Vec3 &a = P_[F_(f, 0)], &b = P_[F_(f, 1)], &d = P_[F_(f, 2)];
      const Vec3 ab = b - a, ad = d - a, nn = ab.cross(ad);
      const double n2 = nn.squaredNorm();
      double w[3];
      w[1] = (c - a).cross(ad).dot(nn) / n2;
      w[2] = ab.cross(c - a).dot(nn) / n2;
      w[0] = 1 - w[1] - w[2];
      constexpr double eps = 1e-10;
      int zeros = 0, free_corner = -1, zero_corner = -1;
      for (int k = 0; k < 3; ++k) {
        if (w[k] < eps) ++zeros, zero_corner = k;
        else free_corner = k;
      }
      if (zeros >= 2) n = vertex_normal_[F_(f, free_corner)];
      else if (zeros == 1) n = edge_normal_[edges_.face_edges[f][(zero_corner + 1) % 3]];  // edge opposite corner
      else n = face_normal_[f];
    } else {
      const auto [cp, it] = segment_tree_->closest_point_and_primitive(
          q, {to_point(P_[near]), segments_.begin() + first_face_[near]});
      const Index s = static_cast<Index>(it - segments_.begin());
      c = to_vec(cp);
      const Vec3 &a = P_[F_(s, 0)], &b = P_[F_(s, 1)];
      const double t = (c - a).dot(b - a) / (b - a).squaredNorm();
      if (t < 1e-10) n = vertex_normal_[F_(s, 0)];
      else if (t > 1 - 1e-10) n = vertex_normal_[F_(s, 1)];
      else n = face_normal_[s];
    }
    const double d = (x - c).norm();
    return (x - c).dot(n) < 0 ? -d : d;
  }

  // Whether the mesh comes within `tol` of x (in the max norm).
  bool touches(const Vec3& x, double tol) const {
    const CGAL::Bbox_3 box(x[0] - tol, x[1] - tol, x[2] - tol, x[0] + tol, x[1] + tol, x[2] + tol);
    return D_ == 3 ? triangle_tree_->do_intersect(box) : segment_tree_->do_intersect(box);
  }

  bool intersects_triangle(const Vec3& a, const Vec3& b, const Vec3& c) const {
    const Point pa = to_point(a), pb = to_point(b), pc = to_point(c);
    if (CGAL::collinear(pa, pb, pc))
      return intersects_segment(a, b) || intersects_segment(b, c) || intersects_segment(c, a);
    return triangle_tree_->do_intersect(Triangle(pa, pb, pc));
  }
  bool intersects_segment(const Vec3& a, const Vec3& b) const {
    if (a == b) return D_ == 3 ? triangle_tree_->do_intersect(to_point(a)) : segment_tree_->do_intersect(to_point(a));
    const Segment s(to_point(a), to_point(b));
    return D_ == 3 ? triangle_tree_->do_intersect(s) : segment_tree_->do_intersect(s);
  }

 private:
  const std::vector<Vec3>& P_;
  const SimplexMatrix& F_;
  int D_;
  std::vector<Triangle> triangles_;
  std::vector<Segment> segments_;
  std::unique_ptr<TriangleTree> triangle_tree_;
  std::unique_ptr<SegmentTree> segment_tree_;
  EdgeTable edges_;
  std::vector<Vec3> face_normal_, vertex_normal_, edge_normal_;
  std::vector<Index> first_face_;
};

// The mesh's query structure, with CGAL's failures in our words.
MeshQuery mesh_query(const std::vector<Vec3>& P, const SimplexMatrix& F) {
  return translating_cgal_failures("building the search tree of a mesh of " + std::to_string(F.rows()) + " faces",
                                   [&] { return MeshQuery(P, F); });
}

}  // namespace

std::vector<bool> faces_intersecting_mesh(const PointMatrix& faces_V, const SimplexMatrix& faces, const PointMatrix& V,
                                          const SimplexMatrix& F) {
  const int D = static_cast<int>(V.cols());
  if ((D != 2 && D != 3) || F.cols() != D || faces_V.cols() != D || (faces.rows() > 0 && faces.cols() != D))
    fail<InputError>("faces_intersecting_mesh needs segments in R^2 or triangles in R^3 on both sides");
  {
    for (Index f = 0; f < faces.rows(); ++f)
      for (int k = 0; k < D; ++k)
        if (faces(f, k) < 0 || faces(f, k) >= faces_V.rows())
          fail<InputError>("face ", f, " refers to vertex ", faces(f, k), ", outside 0..", faces_V.rows() - 1);
    for (Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < D; ++k)
        if (F(f, k) < 0 || F(f, k) >= V.rows())
          fail<InputError>("mesh face ", f, " refers to vertex ", F(f, k), ", outside 0..", V.rows() - 1);
  }
  const auto P = to_vec3(V);
  const auto Q = to_vec3(faces_V);
  const MeshQuery mesh = mesh_query(P, F);
  std::vector<bool> out(static_cast<size_t>(faces.rows()));
  for (Index f = 0; f < faces.rows(); ++f)
    out[f] = D == 3 ? mesh.intersects_triangle(Q[faces(f, 0)], Q[faces(f, 1)], Q[faces(f, 2)])
                    : mesh.intersects_segment(Q[faces(f, 0)], Q[faces(f, 1)]);
  return out;
}

namespace {

void check_options(const SkeletonOptions& options) {
  if (!options.internal && !options.external)
    fail<InputError>("ask for the internal and/or the external skeleton (neither was requested)");
  if (options.wrap != WrapShape::None && options.wrap_density < 1)
    fail<InputError>("wrap density must be >= 1, got ", options.wrap_density);
  if (options.wrap != WrapShape::None && !(options.wrap_margin > 0))
    fail<InputError>("wrap margin must be > 0, got ", options.wrap_margin);
}

// The Voronoi diagram's sites: the mesh vertices, then the wrap's points.
Delaunay voronoi_of_sites(const PointMatrix& M, const SkeletonOptions& options) {
  const PointMatrix W = wrap_points(M, options.wrap, options.wrap_density, options.wrap_margin);
  PointMatrix sites(M.rows() + W.rows(), M.cols());
  sites << M, W;
  return qhull_delaunay(sites);
}

std::vector<Vec3> rows_as_vec3(const PointMatrix& X) {
  std::vector<Vec3> out(static_cast<size_t>(X.rows()), Vec3::Zero());
  for (Index r = 0; r < X.rows(); ++r)
    for (int k = 0; k < X.cols(); ++k) out[r][k] = X(r, k);
  return out;
}

// Side of the mesh per Voronoi vertex: -1 inside, +1 outside, 0 on the mesh
// (a tiny box query), 2 for a vertex of no polygon. Sides are propagated
// along Voronoi edges that do not cross the mesh (exact segment tests), with
// an exact signed distance (pseudonormal sign) to start each region.
std::vector<signed char> classify_sides(const BisectorPolygons& polygons, const std::vector<Vec3>& centre,
                                        const MeshQuery& mesh, double on_tolerance) {
  const VoronoiEdgeGraph graph = voronoi_edge_graph(polygons, centre.size());
  std::vector<signed char> side(centre.size(), 2);
  for (size_t c = 0; c < centre.size(); ++c)
    if (graph.site[c] >= 0 && mesh.touches(centre[c], on_tolerance)) side[c] = 0;
  std::vector<Index> queue;
  for (size_t seed = 0; seed < centre.size(); ++seed) {
    if (graph.site[seed] < 0 || side[seed] != 2) continue;
    side[seed] = mesh.signed_distance(centre[seed], graph.site[seed]) < 0 ? -1 : 1;
    queue.assign(1, static_cast<Index>(seed));
    while (!queue.empty()) {
      const Index u = queue.back();
      queue.pop_back();
      for (Index e = graph.first[u]; e < graph.first[u + 1]; ++e) {
        const Index v = graph.neighbour[e];
        if (side[v] != 2) continue;
        if (centre[u] == centre[v] || !mesh.intersects_segment(centre[u], centre[v])) {
          side[v] = side[u];
          queue.push_back(v);
        }
      }
    }
  }
  return side;
}

// What a bisector polygon is judged against, shared by all of them.
struct ExtractionInputs {
  int D;
  Index n;                                             // mesh vertices
  const std::vector<Vec3>& P;                          // mesh vertex positions
  const std::vector<Vec3>& centre;                     // Voronoi vertices
  const std::vector<signed char>& side;                // per Voronoi vertex (classify_sides)
  const MeshQuery& mesh;
  const std::vector<std::vector<Index>>& neighbours;  // sorted, per mesh vertex
  const SkeletonOptions& options;
  double shrink;          // how far intersection tests stay away from corners on the mesh
  double hull_tolerance;  // how far outside a hull plane still counts as on it
};

// Decides each bounded bisector polygon: discarded when it is local to a
// mesh edge or crosses the mesh, skipped when its side was not asked for,
// clipped to the convex hull on the external side, then welded into the
// assembly. Counts what it sees in the skeleton's diagnostics.
class BisectorJudge {
 public:
  BisectorJudge(const ExtractionInputs& in, const Hull& hull, SkeletonAssembly& assembly, VoronoiSkeleton& stats)
      : in_(in), hull_(hull), hull_normal_(rows_as_vec3(hull.normals)), in_hull_(in.centre.size(), -1),
        assembly_(assembly), stats_(stats) {}

  void handle(Index a, Index b, const std::vector<Index>& ring, const std::vector<Index>& link) {
    ++stats_.bisectors;
    if (adjacent(a, b) && holds_edge_midpoint(a, b, ring)) return discard(a, b);
    const int side = polygon_side(a, ring);
    if (side == 0) return discard(a, b);
    const bool inside = side < 0;
    // Not requested: skipped before the costly intersection test.
    if (inside ? !in_.options.internal : !in_.options.external) return;
    std::vector<Corner> poly = corners(ring);
    if (!inside && !clip_to_hull(ring, poly)) return;
    if (crosses_mesh(poly)) return discard(a, b);
    emit(a, b, ring, link, poly, inside);
  }

  // Attachment candidates (§8.6.2): Voronoi edges (link vertex, centre, centre) of kept polygons.
  const std::vector<std::array<Index, 3>>& edge_candidates() const { return edge_candidates_; }

 private:
  bool adjacent(Index a, Index b) const {
    return std::binary_search(in_.neighbours[a].begin(), in_.neighbours[a].end(), b);
  }

  void discard(Index a, Index b) {
    ++stats_.discarded;
    if (adjacent(a, b)) return;
    ++stats_.discarded_nonlocal;
    const auto &na = in_.neighbours[a], &nb = in_.neighbours[b];
    std::vector<Index> common;
    std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
    if (common.empty()) ++stats_.discarded_far;
  }

  // A mesh edge's own bisector holds the edge's midpoint, a point of the mesh,
  // when the edge is Gabriel: it is local (it crosses or touches the mesh
  // there) and never skeleton, even when the midpoint is its corner on the
  // mesh (Figure 7.10).
  bool holds_edge_midpoint(Index a, Index b, const std::vector<Index>& ring) const {
    const auto& centre = in_.centre;
    const Vec3 mid = 0.5 * (in_.P[a] + in_.P[b]), axis = in_.P[b] - in_.P[a];
    if (in_.D == 2) {
      const Vec3 d = centre[ring[1]] - centre[ring[0]];
      const double t = (mid - centre[ring[0]]).dot(d);
      return t >= -1e-9 * d.squaredNorm() && t <= (1 + 1e-9) * d.squaredNorm();
    }
    const size_t m = ring.size();
    bool holds = true;
    for (int orientation : {1, -1}) {
      holds = true;
      for (size_t i = 0; i < m && holds; ++i) {
        const Vec3 &u = centre[ring[i]], &w = centre[ring[(i + 1) % m]];
        const double tol = 1e-9 * (w - u).norm() * (mid - u).norm() * axis.norm();
        holds = orientation * (w - u).cross(mid - u).dot(axis) >= -tol;
      }
      if (holds) break;
    }
    return holds;
  }

  // -1 inside, +1 outside, 0 crossing the mesh (corners strictly on both
  // sides). A polygon with every corner on the mesh is decided by its centroid.
  int polygon_side(Index a, const std::vector<Index>& ring) const {
    bool any_in = false, any_out = false;
    for (Index c : ring) {
      if (in_.side[c] < 0) any_in = true;
      else if (in_.side[c] > 0) any_out = true;
    }
    if (any_in && any_out) return 0;
    if (any_in) return -1;
    if (any_out) return 1;
    Vec3 g = Vec3::Zero();
    for (Index c : ring) g += in_.centre[c];
    return in_.mesh.signed_distance(g / static_cast<double>(ring.size()), a) < 0 ? -1 : 1;
  }

  std::vector<Corner> corners(const std::vector<Index>& ring) const {
    const size_t m = ring.size();
    std::vector<Corner> poly;
    poly.reserve(m + 4);
    for (size_t i = 0; i < (in_.D == 2 ? 2 : m); ++i)
      poly.push_back({in_.centre[ring[i]], {ring[i], -1, -1}, {ring[i], ring[(i + 1) % m]}});
    return poly;
  }

  bool inside_hull(Index c) {
    if (in_hull_[c] < 0) {
      in_hull_[c] = 1;
      for (Index h = 0; h < hull_.offsets.size(); ++h)
        if (hull_normal_[h].dot(in_.centre[c]) + hull_.offsets[h] > in_.hull_tolerance) {
          in_hull_[c] = 0;
          break;
        }
    }
    return in_hull_[c] == 1;
  }

  // Clips the polygon to the convex hull; false when nothing of it is left.
  bool clip_to_hull(const std::vector<Index>& ring, std::vector<Corner>& poly) {
    bool all_in = true;
    for (Index c : ring) all_in = all_in && inside_hull(c);
    if (all_in) return true;
    for (Index h = 0; h < hull_.offsets.size() && !poly.empty(); ++h) clip_to_plane(h, poly);
    return poly.size() >= static_cast<size_t>(in_.D);
  }

  void clip_to_plane(Index h, std::vector<Corner>& poly) {
    const Vec3& nh = hull_normal_[h];
    const double off = hull_.offsets[h];
    bool outside_any = false;
    std::vector<double> dist(poly.size());
    for (size_t i = 0; i < poly.size(); ++i) {
      dist[i] = nh.dot(poly[i].p) + off;
      outside_any = outside_any || dist[i] > in_.hull_tolerance;
    }
    if (!outside_any) return;
    std::vector<Corner> next;
    const size_t count = poly.size();
    const size_t edges = in_.D == 2 ? 1 : count;
    for (size_t i = 0; i < edges; ++i) {
      const size_t j = (i + 1) % count;
      const bool in_i = dist[i] <= in_.hull_tolerance, in_j = dist[j] <= in_.hull_tolerance;
      if (in_i) {
        next.push_back(poly[i]);
        if (!in_j) {
          Corner x = cut(h, poly[i], poly[j], dist[i], dist[j]);
          x.carrier = {-1, -1};
          next.push_back(x);
        }
      } else if (in_j) {
        Corner x = cut(h, poly[i], poly[j], dist[i], dist[j]);
        x.carrier = poly[i].carrier;
        next.push_back(x);
      }
    }
    if (in_.D == 2 && dist[1] <= in_.hull_tolerance) next.push_back(poly[1]);
    poly = std::move(next);
  }

  // Where hull plane h cuts the polygon edge from -> to. A cut of a Voronoi
  // edge is computed from the edge's ends, canonically, and keyed by the
  // edge and plane so that every polygon around the edge welds to it.
  Corner cut(Index h, const Corner& from, const Corner& to, double dist_from, double dist_to) {
    Corner x;
    const auto car = from.carrier;
    if (car[0] >= 0) {
      const Vec3& nh = hull_normal_[h];
      const double off = hull_.offsets[h];
      const auto& centre = in_.centre;
      const Index u = std::min(car[0], car[1]), v = std::max(car[0], car[1]);
      const double du = nh.dot(centre[u]) + off, dv = nh.dot(centre[v]) + off;
      x.p = centre[u] + (du / (du - dv)) * (centre[v] - centre[u]);
      x.key = {u, v, h};
    } else {
      x.p = from.p + (dist_from / (dist_from - dist_to)) * (to.p - from.p);
      x.key = {-2, serial_++, 0};
    }
    return x;
  }

  bool on_mesh(const Corner& c) const { return c.key[1] == -1 && in_.side[c.key[0]] == 0; }

  // Exact intersection test, staying `shrink` away from corners on the mesh.
  bool crosses_mesh(const std::vector<Corner>& poly) const {
    const int D = in_.D;
    const size_t count = poly.size();
    std::vector<Vec3> test;
    for (size_t i = 0; i < count; ++i) {
      if (!on_mesh(poly[i])) {
        test.push_back(poly[i].p);
        continue;
      }
      const Vec3& p = poly[i].p;
      const size_t around[2] = {(i + count - 1) % count, (i + 1) % count};
      for (int s = 0; s < 2; ++s) {
        if (D == 2 && around[s] == i) continue;
        const Vec3 d = poly[around[s]].p - p;
        const double len = d.norm();
        if (len == 0) continue;
        test.push_back(p + std::min(in_.shrink, 0.25 * len) / len * d);
        if (D == 2) break;
      }
    }
    if (D == 2) return test.size() >= 2 && in_.mesh.intersects_segment(test[0], test.back());
    for (size_t i = 1; i + 1 < test.size(); ++i)
      if (in_.mesh.intersects_triangle(test[0], test[i], test[i + 1])) return true;
    return false;
  }

  // Welded corners, fan triangles oriented from site a towards site b.
  void emit(Index a, Index b, const std::vector<Index>& ring, const std::vector<Index>& link,
            const std::vector<Corner>& poly, bool inside) {
    std::vector<Index> ids;
    for (const auto& c : poly) {
      const Index id = assembly_.vertex(c, on_mesh(c));
      if (ids.empty() || ids.back() != id) ids.push_back(id);
    }
    while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
    if (ids.size() < static_cast<size_t>(in_.D)) return;
    const Index polygon_id = assembly_.begin_polygon(a, b);
    if (in_.D == 2) {
      assembly_.add_face({ids[0], ids[1], -1}, inside, a, b, polygon_id);
      return;
    }
    Vec3 normal = Vec3::Zero();
    for (size_t i = 0; i < ids.size(); ++i)
      normal += assembly_.position(ids[i]).cross(assembly_.position(ids[(i + 1) % ids.size()]));
    const bool flip = normal.dot(in_.P[b] - in_.P[a]) < 0;
    for (size_t i = 1; i + 1 < ids.size(); ++i) {
      std::array<Index, 3> t = {ids[0], ids[i], ids[i + 1]};
      if (t[0] == t[1] || t[0] == t[2]) continue;  // a degenerate ring revisiting a vertex
      if (flip) std::swap(t[1], t[2]);
      assembly_.add_face(t, inside, a, b, polygon_id);
    }
    if (in_.options.attach)
      for (size_t i = 0; i < ring.size(); ++i)
        if (link[i] < in_.n) edge_candidates_.push_back({link[i], ring[i], ring[(i + 1) % ring.size()]});
  }

  const ExtractionInputs& in_;
  const Hull& hull_;
  std::vector<Vec3> hull_normal_;
  std::vector<signed char> in_hull_;  // per Voronoi vertex: -1 not known yet, else 0 / 1
  SkeletonAssembly& assembly_;
  VoronoiSkeleton& stats_;
  std::vector<std::array<Index, 3>> edge_candidates_;
  Index serial_ = 0;  // keys the cuts of edges that no other polygon shares
};

// Bisector polygons judged between two step()s of the interrupter.
constexpr size_t kPolygonsPerStep = 1024;

// The skeleton of the separable mesh (out.refined_vertices, out.refined_faces).
void extract(const SkeletonOptions& options, const Interrupter& interrupter, VoronoiSkeleton& out) {
  const int D = static_cast<int>(out.refined_vertices.cols());
  const PointMatrix& M = out.refined_vertices;
  const SimplexMatrix& MF = out.refined_faces;
  const Index n = static_cast<Index>(M.rows());
  const std::vector<Vec3> P = to_vec3(M);
  const double diag = (M.colwise().maxCoeff() - M.colwise().minCoeff()).norm();
  const double on_tolerance = 1e-9 * diag;  // Voronoi vertices this close lie on the mesh (Figure 7.10)

  interrupter.step("voronoi", 0.4);
  const Delaunay del = voronoi_of_sites(M, options);
  const std::vector<Vec3> centre = rows_as_vec3(del.centers);
  const MeshQuery mesh = mesh_query(P, MF);
  const auto neighbours = vertex_neighbours(MF, n);
  const Hull hull = options.external ? qhull_convex_hull(M) : Hull{};
  // Collected first so that the sides of their Voronoi vertices are found together.
  const BisectorPolygons polygons = bisector_polygons(del, n);
  interrupter.step("sides", 0.5);
  const std::vector<signed char> side = classify_sides(polygons, centre, mesh, on_tolerance);

  const ExtractionInputs inputs{D, n, P, centre, side, mesh, neighbours, options, 1e-4 * diag, 1e-12 * diag};
  SkeletonAssembly assembly(centre.size(), n);
  BisectorJudge judge(inputs, hull, assembly, out);
  for (size_t k = 0; k < polygons.size(); ++k) {
    if (k % kPolygonsPerStep == 0)
      interrupter.step("bisectors", loop_fraction(0.55, 0.95, static_cast<long long>(k),
                                                  static_cast<long long>(polygons.size())));
    judge.handle(polygons.a[k], polygons.b[k], polygons.corners(k), polygons.links(k));
  }
  interrupter.step("assembly", 0.95);
  assembly.drop_unused(D);
  assembly.write(out, D);
  out.attachment = options.attach
                       ? attachment_simplices(del, n, D, assembly, neighbours, judge.edge_candidates())
                       : SimplexMatrix(0, D);
}

}  // namespace

VoronoiSkeleton voronoi_skeleton(const PointMatrix& V, const SimplexMatrix& F, const SkeletonOptions& options,
                                 const Interrupter& interrupter) {
  interrupter.step("checks", 0);
  check_options(options);
  const auto start = std::chrono::steady_clock::now();
  VoronoiSkeleton out;
  out.dihedral = dihedral_test(V, F, options.dihedral_limit);  // also validates the input
  {
    interrupter.step("separability", 0.05);
    SeparabilityResult sep = make_voronoi_separable(V, F, options.max_iterations, options.rule);
    out.refined_vertices = std::move(sep.vertices);
    out.refined_faces = std::move(sep.faces);
    out.separable = sep.separable;
    out.iterations = sep.iterations;
    out.splits = sep.splits;
  }
  out.seconds_separability = seconds_since(start);
  const auto extraction_start = std::chrono::steady_clock::now();
  extract(options, interrupter, out);
  out.seconds_extraction = seconds_since(extraction_start);
  return out;
}

}  // namespace animanifold
