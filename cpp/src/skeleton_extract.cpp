// Voronoi skeleton extraction (§7.3, §7.4) and attachment (§8.6.2): the
// bisector polygons b_ij of the Voronoi diagram of a separable mesh's
// vertices that do not intersect the mesh, classified internal/external and
// clipped to the convex hull. Mesh queries use CGAL's AABB tree with exact
// predicates (Epick).
#include "animanifold/errors.hpp"
#include "animanifold/skeleton.hpp"
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

// A polygon corner during clipping: its position, how it is keyed for
// welding, and the carrier of the edge leaving it (a Voronoi edge u-v, or -1
// for an edge cut along a hull plane).
struct Corner {
  Vec3 p;
  std::array<Index, 3> key;  // {center, -1, -1}, {u, v, plane} or {-2, serial, 0}
  std::array<Index, 2> carrier;
};

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
  const MeshQuery mesh(P, F);
  std::vector<bool> out(static_cast<size_t>(faces.rows()));
  for (Index f = 0; f < faces.rows(); ++f)
    out[f] = D == 3 ? mesh.intersects_triangle(Q[faces(f, 0)], Q[faces(f, 1)], Q[faces(f, 2)])
                    : mesh.intersects_segment(Q[faces(f, 0)], Q[faces(f, 1)]);
  return out;
}

VoronoiSkeleton voronoi_skeleton(const PointMatrix& V, const SimplexMatrix& F, const SkeletonOptions& options) {
  if (!options.internal && !options.external)
    fail<InputError>("ask for the internal and/or the external skeleton (neither was requested)");
  if (options.wrap != WrapShape::None && options.wrap_density < 1)
    fail<InputError>("wrap density must be >= 1, got ", options.wrap_density);
  if (options.wrap != WrapShape::None && !(options.wrap_margin > 0))
    fail<InputError>("wrap margin must be > 0, got ", options.wrap_margin);
  const auto start = std::chrono::steady_clock::now();
  VoronoiSkeleton out;
  out.dihedral = dihedral_test(V, F, options.dihedral_limit);  // also validates the input
  {
    SeparabilityResult sep = make_voronoi_separable(V, F, options.max_iterations, options.rule);
    out.refined_vertices = std::move(sep.vertices);
    out.refined_faces = std::move(sep.faces);
    out.separable = sep.separable;
    out.iterations = sep.iterations;
    out.splits = sep.splits;
  }
  out.seconds_separability = seconds_since(start);
  const auto extraction_start = std::chrono::steady_clock::now();

  const int D = static_cast<int>(V.cols());
  const PointMatrix& M = out.refined_vertices;
  const SimplexMatrix& MF = out.refined_faces;
  const Index n = static_cast<Index>(M.rows());
  const std::vector<Vec3> P = to_vec3(M);
  const double diag = (M.colwise().maxCoeff() - M.colwise().minCoeff()).norm();
  const double on_tolerance = 1e-9 * diag;   // Voronoi vertices this close lie on the mesh (Figure 7.10)
  const double shrink = 1e-4 * diag;         // how far intersection tests stay away from them
  const double hull_tolerance = 1e-12 * diag;

  // Voronoi diagram of the mesh vertices and the wrap.
  const PointMatrix W = wrap_points(M, options.wrap, options.wrap_density, options.wrap_margin);
  PointMatrix sites(n + W.rows(), D);
  sites << M, W;
  const Delaunay del = qhull_delaunay(sites);
  std::vector<Vec3> centre(static_cast<size_t>(del.centers.rows()), Vec3::Zero());
  for (Index c = 0; c < del.centers.rows(); ++c)
    for (int k = 0; k < D; ++k) centre[c][k] = del.centers(c, k);

  const MeshQuery mesh(P, MF);
  const auto neighbours = vertex_neighbours(MF, n);
  auto adjacent = [&](Index a, Index b) {
    return std::binary_search(neighbours[a].begin(), neighbours[a].end(), b);
  };
  Hull hull;
  if (options.external) hull = qhull_convex_hull(M);
  const Index H = static_cast<Index>(hull.offsets.size());
  std::vector<Vec3> hull_normal(static_cast<size_t>(H), Vec3::Zero());
  for (Index h = 0; h < H; ++h)
    for (int k = 0; k < D; ++k) hull_normal[h][k] = hull.normals(h, k);

  // Per Voronoi vertex: which side of the mesh it is on (-1 inside, +1 outside,
  // 0 on the mesh, 2 not computed yet); filled before the polygons are handled.
  std::vector<signed char> side_of(centre.size(), 2);
  auto exact_side = [&](Index c, Index near) -> signed char {
    return mesh.signed_distance(centre[c], near) < 0 ? -1 : 1;
  };
  std::vector<signed char> in_hull(centre.size(), -1);
  auto inside_hull = [&](Index c) {
    if (in_hull[c] < 0) {
      in_hull[c] = 1;
      for (Index h = 0; h < H; ++h)
        if (hull_normal[h].dot(centre[c]) + hull.offsets[h] > hull_tolerance) {
          in_hull[c] = 0;
          break;
        }
    }
    return in_hull[c] == 1;
  };

  // Output assembly: welded vertices keyed by Voronoi vertex or hull cut.
  std::vector<Index> centre_out(centre.size(), -1);
  std::map<std::array<Index, 3>, Index> cut_out;
  std::vector<Vec3> out_vertices;
  std::vector<Index> out_on_mesh;
  auto emit_vertex = [&](const Corner& c) -> Index {
    if (c.key[1] == -1) {
      Index& slot = centre_out[c.key[0]];
      if (slot < 0) {
        slot = static_cast<Index>(out_vertices.size());
        out_vertices.push_back(c.p);
        out_on_mesh.push_back(side_of[c.key[0]] == 0 ? 1 : 0);
      }
      return slot;
    }
    if (c.key[0] == -2) {
      out_vertices.push_back(c.p);
      out_on_mesh.push_back(0);
      return static_cast<Index>(out_vertices.size() - 1);
    }
    auto [it, fresh] = cut_out.emplace(c.key, static_cast<Index>(out_vertices.size()));
    if (fresh) {
      out_vertices.push_back(c.p);
      out_on_mesh.push_back(0);
    }
    return it->second;
  };
  std::vector<std::array<Index, 3>> out_faces;
  std::vector<Index> out_side, out_polygon;
  std::vector<std::array<Index, 2>> out_sites;
  std::vector<char> is_site(static_cast<size_t>(n), 0);
  // Attachment candidates (§8.6.2): Voronoi edges (link vertex, centre, centre) of kept polygons.
  std::vector<std::array<Index, 3>> edge_candidates;
  Index serial = 0, polygon_count = 0;

  // Handles one bounded bisector polygon (centre ids in cyclic order; two in 2D).
  // `link` holds, per polygon edge i -> i+1, the Delaunay vertex dual to it (3D).
  auto handle = [&](Index a, Index b, const std::vector<Index>& ring, const std::vector<Index>& link) {
    ++out.bisectors;
    auto discard = [&] {
      ++out.discarded;
      if (!adjacent(a, b)) {
        ++out.discarded_nonlocal;
        const auto &na = neighbours[a], &nb = neighbours[b];
        std::vector<Index> common;
        std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
        if (common.empty()) ++out.discarded_far;
      }
    };
    // A mesh edge's own bisector holds the edge's midpoint, a point of the mesh,
    // when the edge is Gabriel: it is local (it crosses or touches the mesh
    // there) and never skeleton, even when the midpoint is its corner on the
    // mesh (Figure 7.10).
    if (adjacent(a, b)) {
      const Vec3 mid = 0.5 * (P[a] + P[b]), axis = P[b] - P[a];
      bool holds = true;
      const size_t m = ring.size();
      if (D == 2) {
        const Vec3 d = centre[ring[1]] - centre[ring[0]];
        const double t = (mid - centre[ring[0]]).dot(d);
        holds = t >= -1e-9 * d.squaredNorm() && t <= (1 + 1e-9) * d.squaredNorm();
      } else {
        for (int orientation : {1, -1}) {
          holds = true;
          for (size_t i = 0; i < m && holds; ++i) {
            const Vec3 &u = centre[ring[i]], &w = centre[ring[(i + 1) % m]];
            const double tol = 1e-9 * (w - u).norm() * (mid - u).norm() * axis.norm();
            holds = orientation * (w - u).cross(mid - u).dot(axis) >= -tol;
          }
          if (holds) break;
        }
      }
      if (holds) return discard();
    }
    // Side of the mesh: a polygon with corners strictly inside and outside crosses it.
    bool any_in = false, any_out = false;
    for (Index c : ring) {
      if (side_of[c] < 0) any_in = true;
      else if (side_of[c] > 0) any_out = true;
    }
    if (any_in && any_out) return discard();
    bool inside = any_in;
    if (!any_in && !any_out) {  // every corner on the mesh: decide by the centroid
      Vec3 g = Vec3::Zero();
      for (Index c : ring) g += centre[c];
      inside = mesh.signed_distance(g / static_cast<double>(ring.size()), a) < 0;
    }
    if (inside ? !options.internal : !options.external) {
      // Not requested, but still an intersection test for the statistics would cost time: skip.
      return;
    }
    // Corners, clipped to the convex hull on the external side.
    const size_t m = ring.size();
    std::vector<Corner> poly;
    poly.reserve(m + 4);
    for (size_t i = 0; i < (D == 2 ? 2 : m); ++i)
      poly.push_back({centre[ring[i]], {ring[i], -1, -1}, {ring[i], ring[(i + 1) % m]}});
    if (!inside) {
      bool all_in = true;
      for (Index c : ring) all_in = all_in && inside_hull(c);
      if (!all_in) {
        for (Index h = 0; h < H && !poly.empty(); ++h) {
          const Vec3& nh = hull_normal[h];
          const double off = hull.offsets[h];
          bool outside_any = false;
          std::vector<double> dist(poly.size());
          for (size_t i = 0; i < poly.size(); ++i) {
            dist[i] = nh.dot(poly[i].p) + off;
            outside_any = outside_any || dist[i] > hull_tolerance;
          }
          if (!outside_any) continue;
          std::vector<Corner> next;
          const size_t count = poly.size();
          const size_t edges = D == 2 ? 1 : count;
          for (size_t i = 0; i < edges; ++i) {
            const size_t j = (i + 1) % count;
            const bool in_i = dist[i] <= hull_tolerance, in_j = dist[j] <= hull_tolerance;
            auto cut = [&]() {
              Corner x;
              const auto car = poly[i].carrier;
              if (car[0] >= 0) {  // on a Voronoi edge: computed from its ends, canonically
                const Index u = std::min(car[0], car[1]), v = std::max(car[0], car[1]);
                const double du = nh.dot(centre[u]) + off, dv = nh.dot(centre[v]) + off;
                x.p = centre[u] + (du / (du - dv)) * (centre[v] - centre[u]);
                x.key = {u, v, h};
              } else {
                x.p = poly[i].p + (dist[i] / (dist[i] - dist[j])) * (poly[j].p - poly[i].p);
                x.key = {-2, serial++, 0};
              }
              return x;
            };
            if (in_i) {
              next.push_back(poly[i]);
              if (!in_j) {
                Corner x = cut();
                x.carrier = {-1, -1};
                next.push_back(x);
              }
            } else if (in_j) {
              Corner x = cut();
              x.carrier = poly[i].carrier;
              next.push_back(x);
            }
          }
          if (D == 2 && dist[1] <= hull_tolerance) next.push_back(poly[1]);
          poly = std::move(next);
        }
        if (poly.size() < static_cast<size_t>(D)) return;  // outside the hull
      }
    }
    // Exact intersection test, staying `shrink` away from corners on the mesh.
    const size_t count = poly.size();
    std::vector<Vec3> test;
    for (size_t i = 0; i < count; ++i) {
      const bool on = poly[i].key[1] == -1 && side_of[poly[i].key[0]] == 0;
      if (!on) {
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
        test.push_back(p + std::min(shrink, 0.25 * len) / len * d);
        if (D == 2) break;
      }
    }
    bool hit = false;
    if (D == 2) {
      hit = test.size() >= 2 && mesh.intersects_segment(test[0], test.back());
    } else {
      for (size_t i = 1; i + 1 < test.size() && !hit; ++i) hit = mesh.intersects_triangle(test[0], test[i], test[i + 1]);
    }
    if (hit) return discard();

    // Emit: welded corners, fan triangles oriented from site a towards site b.
    std::vector<Index> ids;
    for (const auto& c : poly) {
      const Index id = emit_vertex(c);
      if (ids.empty() || ids.back() != id) ids.push_back(id);
    }
    while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
    if (ids.size() < static_cast<size_t>(D)) return;
    const Index polygon_id = polygon_count++;
    is_site[a] = is_site[b] = 1;
    const Vec3 ab = P[b] - P[a];
    if (D == 2) {
      out_faces.push_back({ids[0], ids[1], -1});
      out_side.push_back(inside ? 0 : 1);
      out_sites.push_back({a, b});
      out_polygon.push_back(polygon_id);
    } else {
      Vec3 normal = Vec3::Zero();
      for (size_t i = 0; i < ids.size(); ++i)
        normal += out_vertices[ids[i]].cross(out_vertices[ids[(i + 1) % ids.size()]]);
      const bool flip = normal.dot(ab) < 0;
      for (size_t i = 1; i + 1 < ids.size(); ++i) {
        std::array<Index, 3> t = {ids[0], ids[i], ids[i + 1]};
        if (t[0] == t[1] || t[0] == t[2]) continue;  // a degenerate ring revisiting a vertex
        if (flip) std::swap(t[1], t[2]);
        out_faces.push_back(t);
        out_side.push_back(inside ? 0 : 1);
        out_sites.push_back({a, b});
        out_polygon.push_back(polygon_id);
      }
      if (options.attach)
        for (size_t i = 0; i < m; ++i)
          if (link[i] < n) edge_candidates.push_back({link[i], ring[i], ring[(i + 1) % m]});
    }
  };

  // Bounded bisector polygons, collected first so that the sides of their
  // Voronoi vertices can be found together.
  std::vector<Index> poly_a, poly_b, ring_start{0}, ring_flat, link_flat;
  auto collect = [&](Index a, Index b, const std::vector<Index>& ring, const std::vector<Index>& link) {
    poly_a.push_back(a);
    poly_b.push_back(b);
    ring_flat.insert(ring_flat.end(), ring.begin(), ring.end());
    if (link.empty()) link_flat.insert(link_flat.end(), ring.size(), -1);
    else link_flat.insert(link_flat.end(), link.begin(), link.end());
    ring_start.push_back(static_cast<Index>(ring_flat.size()));
  };
  // Enumerate the bisectors between mesh vertices: Delaunay edges (a, b), a < b < n.
  const Index T = static_cast<Index>(del.simplices.rows());
  if (D == 2) {
    struct Rec {
      Index a, b, t;
    };
    std::vector<Rec> recs;
    recs.reserve(static_cast<size_t>(T) * 3);
    for (Index t = 0; t < T; ++t)
      for (int k = 0; k < 3; ++k) {
        Index a = del.simplices(t, k), b = del.simplices(t, (k + 1) % 3);
        if (a > b) std::swap(a, b);
        if (b < n) recs.push_back({a, b, t});
      }
    std::sort(recs.begin(), recs.end(),
              [](const Rec& x, const Rec& y) { return std::tie(x.a, x.b, x.t) < std::tie(y.a, y.b, y.t); });
    for (size_t i = 0; i < recs.size();) {
      size_t j = i;
      while (j < recs.size() && recs[j].a == recs[i].a && recs[j].b == recs[i].b) ++j;
      if (j - i == 2) {
        const Index c0 = del.center[recs[i].t], c1 = del.center[recs[i + 1].t];
        if (c0 != c1) collect(recs[i].a, recs[i].b, {c0, c1}, {});
      }
      i = j;
    }
  } else {
    struct Rec {
      Index a, b, c, d, t;
    };
    std::vector<Rec> recs;
    recs.reserve(static_cast<size_t>(T) * 6);
    static constexpr int pairs[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                        {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    for (Index t = 0; t < T; ++t)
      for (const auto& pr : pairs) {
        Index a = del.simplices(t, pr[0]), b = del.simplices(t, pr[1]);
        if (a > b) std::swap(a, b);
        if (b < n) recs.push_back({a, b, del.simplices(t, pr[2]), del.simplices(t, pr[3]), t});
      }
    std::sort(recs.begin(), recs.end(),
              [](const Rec& x, const Rec& y) { return std::tie(x.a, x.b, x.t) < std::tie(y.a, y.b, y.t); });
    std::vector<Index> ring, link, ring_ids, partner;
    std::vector<std::pair<Index, Index>> occurrences;
    std::vector<char> used;
    for (size_t i = 0; i < recs.size();) {
      size_t j = i;
      while (j < recs.size() && recs[j].a == recs[i].a && recs[j].b == recs[i].b) ++j;
      const size_t m = j - i;
      // Walk the tetrahedra around edge (a, b): consecutive ones share a link vertex.
      ring.clear();
      link.clear();
      used.assign(m, 0);
      bool closed = m >= 3;
      if (closed && m <= 12) {
        size_t cur = 0;
        Index from = recs[i].c, to = recs[i].d;
        used[0] = 1;
        ring.push_back(recs[i].t);
        for (size_t step = 1; step < m; ++step) {
          size_t found = m;
          for (size_t k = 0; k < m; ++k)
            if (!used[k] && (recs[i + k].c == to || recs[i + k].d == to)) {
              found = k;
              break;
            }
          if (found == m) {
            closed = false;
            break;
          }
          link.push_back(to);
          used[found] = 1;
          cur = found;
          to = recs[i + cur].c == to ? recs[i + cur].d : recs[i + cur].c;
          ring.push_back(recs[i + cur].t);
        }
        if (closed && to != from) closed = false;
        link.push_back(from);
      } else if (closed) {
        // Large rings (near-cospherical input): pair the tetrahedra through their link vertices.
        occurrences.clear();
        for (size_t k = 0; k < m; ++k) {
          occurrences.push_back({recs[i + k].c, static_cast<Index>(k)});
          occurrences.push_back({recs[i + k].d, static_cast<Index>(k)});
        }
        std::sort(occurrences.begin(), occurrences.end());
        partner.assign(2 * m, -1);  // partner[2k + s]: the other tetrahedron sharing link vertex s of k
        for (size_t o = 0; o < occurrences.size(); o += 2) {
          if (o + 1 >= occurrences.size() || occurrences[o].first != occurrences[o + 1].first ||
              (o + 2 < occurrences.size() && occurrences[o + 2].first == occurrences[o].first)) {
            closed = false;
            break;
          }
          const Index k0 = occurrences[o].second, k1 = occurrences[o + 1].second;
          const Index v = occurrences[o].first;
          partner[2 * k0 + (recs[i + k0].c == v ? 0 : 1)] = k1;
          partner[2 * k1 + (recs[i + k1].c == v ? 0 : 1)] = k0;
        }
        if (closed) {
          Index k = 0, to = recs[i].d;
          for (size_t step = 0; step < m; ++step) {
            ring.push_back(recs[i + k].t);
            link.push_back(to);
            const Index next = partner[2 * k + (recs[i + k].c == to ? 0 : 1)];
            to = recs[i + next].c == to ? recs[i + next].d : recs[i + next].c;
            k = next;
          }
          closed = k == 0;
        }
      }
      if (closed) {
        // Centres, consecutive duplicates (cospherical pieces) merged.
        ring_ids.clear();
        std::vector<Index> links;
        for (size_t k = 0; k < ring.size(); ++k) {
          const Index c = del.center[ring[k]];
          if (!ring_ids.empty() && ring_ids.back() == c) {
            links.back() = link[k];
            continue;
          }
          ring_ids.push_back(c);
          links.push_back(link[k]);
        }
        while (ring_ids.size() > 1 && ring_ids.front() == ring_ids.back()) {
          ring_ids.pop_back();
          links.pop_back();
        }
        if (ring_ids.size() >= 3) collect(recs[i].a, recs[i].b, ring_ids, links);
      }
      i = j;
    }
  }

  // Sides of the Voronoi vertices: on the mesh (a tiny box query), else
  // propagated along Voronoi edges that do not cross the mesh (exact segment
  // tests), with an exact signed distance (pseudonormal sign) to start each
  // region and wherever an edge crosses.
  {
    const size_t P_count = poly_a.size();
    std::vector<std::pair<Index, Index>> pairs;
    pairs.reserve(2 * ring_flat.size());
    std::vector<Index> site_of(centre.size(), -1);
    for (size_t k = 0; k < P_count; ++k) {
      const Index s0 = ring_start[k], s1 = ring_start[k + 1], m = s1 - s0;
      for (Index i = 0; i < m; ++i) {
        const Index u = ring_flat[s0 + i], v = ring_flat[s0 + (i + 1) % m];
        if (site_of[u] < 0) site_of[u] = poly_a[k];
        if (m == 2 && i == 1) break;
        if (u == v) continue;
        pairs.emplace_back(u, v);
        pairs.emplace_back(v, u);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<Index> first(centre.size() + 1, 0);
    for (const auto& pr : pairs) ++first[pr.first + 1];
    for (size_t c = 0; c < centre.size(); ++c) first[c + 1] += first[c];
    for (size_t c = 0; c < centre.size(); ++c)
      if (site_of[c] >= 0 && mesh.touches(centre[c], on_tolerance)) side_of[c] = 0;
    std::vector<Index> queue;
    for (size_t seed = 0; seed < centre.size(); ++seed) {
      if (site_of[seed] < 0 || side_of[seed] != 2) continue;
      side_of[seed] = exact_side(static_cast<Index>(seed), site_of[seed]);
      queue.assign(1, static_cast<Index>(seed));
      while (!queue.empty()) {
        const Index u = queue.back();
        queue.pop_back();
        for (Index e = first[u]; e < first[u + 1]; ++e) {
          const Index v = pairs[e].second;
          if (side_of[v] != 2) continue;
          if (centre[u] == centre[v] || !mesh.intersects_segment(centre[u], centre[v])) {
            side_of[v] = side_of[u];
            queue.push_back(v);
          }
        }
      }
    }
  }
  for (size_t k = 0; k < poly_a.size(); ++k) {
    const Index s0 = ring_start[k], s1 = ring_start[k + 1];
    handle(poly_a[k], poly_b[k], std::vector<Index>(ring_flat.begin() + s0, ring_flat.begin() + s1),
           std::vector<Index>(link_flat.begin() + s0, link_flat.begin() + s1));
  }

  // Drop corners of polygons that collapsed after welding (referenced by no face).
  {
    std::vector<char> used(out_vertices.size(), 0);
    for (const auto& t : out_faces)
      for (int k = 0; k < D; ++k) used[t[k]] = 1;
    std::vector<Index> remap(out_vertices.size(), -1);
    Index kept = 0;
    for (size_t v = 0; v < used.size(); ++v)
      if (used[v]) {
        remap[v] = kept;
        out_vertices[kept] = out_vertices[v];
        out_on_mesh[kept] = out_on_mesh[v];
        ++kept;
      }
    out_vertices.resize(static_cast<size_t>(kept));
    out_on_mesh.resize(static_cast<size_t>(kept));
    for (auto& t : out_faces)
      for (int k = 0; k < D; ++k) t[k] = remap[t[k]];
    for (auto& c : centre_out)
      if (c >= 0) c = remap[c];
  }

  // Results.
  const Index S = static_cast<Index>(out_vertices.size());
  out.vertices.resize(S, D);
  out.on_mesh.resize(S);
  for (Index s = 0; s < S; ++s) {
    for (int k = 0; k < D; ++k) out.vertices(s, k) = out_vertices[s][k];
    out.on_mesh[s] = out_on_mesh[s];
  }
  const Index Fo = static_cast<Index>(out_faces.size());
  out.faces.resize(Fo, D);
  out.side.resize(Fo);
  out.sites.resize(Fo, 2);
  out.polygon.resize(Fo);
  for (Index f = 0; f < Fo; ++f) {
    for (int k = 0; k < D; ++k) out.faces(f, k) = out_faces[f][k];
    out.side[f] = out_side[f];
    out.sites(f, 0) = out_sites[f][0];
    out.sites(f, 1) = out_sites[f][1];
    out.polygon[f] = out_polygon[f];
  }

  // §8.6.2: attach mesh vertices whose cell meets the skeleton only in an edge or a vertex.
  if (options.attach) {
    std::vector<std::array<Index, 3>> attach;
    if (D == 3) {
      std::vector<char> has_edge(static_cast<size_t>(n), 0);
      for (const auto& e : edge_candidates) {
        const Index v = e[0], u = centre_out[e[1]], w = centre_out[e[2]];
        if (is_site[v] || u < 0 || w < 0 || u == w) continue;
        attach.push_back({v, n + u, n + w});
        has_edge[v] = 1;
      }
      // Vertex-only contacts: Voronoi vertices of the vertex's Delaunay tetrahedra on the skeleton.
      std::vector<std::vector<Index>> contact(static_cast<size_t>(n));
      for (Index t = 0; t < T; ++t) {
        const Index c = centre_out[del.center[t]];
        if (c < 0) continue;
        for (int k = 0; k < 4; ++k) {
          const Index v = del.simplices(t, k);
          if (v < n && !is_site[v] && !has_edge[v]) contact[v].push_back(c);
        }
      }
      for (Index v = 0; v < n; ++v) {
        auto& cv = contact[v];
        std::sort(cv.begin(), cv.end());
        cv.erase(std::unique(cv.begin(), cv.end()), cv.end());
      }
      for (Index v = 0; v < n; ++v)
        for (Index c : contact[v]) {
          // Pair with a mesh neighbour touching the same skeleton vertex, else with any neighbour.
          Index partner = -1;
          for (Index w : neighbours[v])
            if (std::binary_search(contact[w].begin(), contact[w].end(), c)) {
              partner = w;
              break;
            }
          if (partner >= 0 && partner < v) continue;  // emitted from the partner's side
          if (partner < 0) partner = neighbours[v].front();
          attach.push_back({v, partner, n + c});
        }
    } else {
      for (Index t = 0; t < T; ++t) {
        const Index c = centre_out[del.center[t]];
        if (c < 0) continue;
        for (int k = 0; k < 3; ++k) {
          const Index v = del.simplices(t, k);
          if (v < n && !is_site[v]) attach.push_back({v, n + c, -1});
        }
      }
      std::sort(attach.begin(), attach.end());
      attach.erase(std::unique(attach.begin(), attach.end()), attach.end());
    }
    out.attachment.resize(static_cast<Index>(attach.size()), D);
    for (size_t r = 0; r < attach.size(); ++r)
      for (int k = 0; k < D; ++k) out.attachment(static_cast<Index>(r), k) = attach[r][k];
  } else {
    out.attachment.resize(0, D);
  }
  out.seconds_extraction = seconds_since(extraction_start);
  return out;
}

}  // namespace animanifold
