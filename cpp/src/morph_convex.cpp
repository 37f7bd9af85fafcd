// convex_hull_fill (morph_convex.hpp): the hull's faces by exact predicates,
// then its 2D faces, its facets and the whole triangulated as stars.
#include "morph_convex.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"

#include <CGAL/Epick_d.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <vector>

namespace animanifold {

namespace {

using K3 = CGAL::Exact_predicates_inexact_constructions_kernel;
using K4 = CGAL::Epick_d<CGAL::Dimension_tag<4>>;
using Triangle = std::array<Index, 3>;
using Tet = std::array<Index, 4>;

K3::Point_3 point3(const PointMatrix& P, Index v) { return {P(v, 0), P(v, 1), P(v, 2)}; }
K4::Point_d point4(const PointMatrix& P, Index v) {
  const std::array<double, 4> c{P(v, 0), P(v, 1), P(v, 2), P(v, 3)};
  return K4::Point_d(c.begin(), c.end());
}

// The sign of the 4D orientation of five points (exact).
CGAL::Orientation orientation4(const PointMatrix& P, const std::array<Index, 5>& ids) {
  std::array<K4::Point_d, 5> points;
  for (int i = 0; i < 5; ++i) points[i] = point4(P, ids[i]);
  return K4::Orientation_d()(points.begin(), points.end());
}

double determinant4(const PointMatrix& P, const std::array<Index, 5>& s) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) m.row(r) = P.row(s[r + 1]) - P.row(s[0]);
  return m.determinant();
}

double triangle_area(const Eigen::RowVector4d& a, const Eigen::RowVector4d& b, const Eigen::RowVector4d& c) {
  const Eigen::RowVector4d u = b - a, w = c - a;
  return 0.5 * std::sqrt(std::max(0.0, u.squaredNorm() * w.squaredNorm() - std::pow(u.dot(w), 2)));
}

Triangle sorted(Triangle t) {
  std::sort(t.begin(), t.end());
  return t;
}

// How far from flat a bend may be, relative to the size, and still count as
// flat: coordinates that went through a rotation (an object's matrix_world
// in float64: ~1e-16; a rotation applied to float32 mesh data: ~6e-8) bend
// a cube's squares and a cylinder's caps by rounding, and the exact predicates alone would call them reflex (or not
// one facet) and send convex inputs down the Delaunay route, whose
// perturbed fill folds through itself on flat sides. Nothing relies on the
// bent faces being flat: the ends are the inputs' own triangles, every
// simplex is checked positive exactly, and the result must fill the hull.
constexpr double kRoundingBend = 1e-6;

// The size of P's first `dims` columns (their bounding box's diagonal).
double size_of(const PointMatrix& P, int dims) {
  return (P.leftCols(dims).colwise().maxCoeff() - P.leftCols(dims).colwise().minCoeff()).norm();
}

// Convex at every edge: the far corner of each face beyond an edge on or
// below the plane of the face on this side (exact orientation, P's first 3
// columns), or above it by no more than rounding (kRoundingBend). With the
// surface enclosing its hull once (below), a closed surface convex at every
// edge is convex; O(faces), unlike testing every vertex against every face.
bool is_convex_at_every_edge(const PointMatrix& P, const SimplexMatrix& F) {
  const double bend = kRoundingBend * size_of(P, 3);
  std::map<std::pair<Index, Index>, std::vector<std::pair<Index, Index>>> faces_of_edge;  // (face, far corner)
  for (Index f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) faces_of_edge[std::minmax(F(f, i), F(f, (i + 1) % 3))].push_back({f, F(f, (i + 2) % 3)});
  for (const auto& [edge, faces] : faces_of_edge) {
    if (faces.size() != 2) return false;
    for (int side = 0; side < 2; ++side) {
      const Index f = faces[side].first, far = faces[1 - side].second;
      if (CGAL::orientation(point3(P, F(f, 0)), point3(P, F(f, 1)), point3(P, F(f, 2)), point3(P, far)) != CGAL::POSITIVE)
        continue;
      const Eigen::Vector3d a = P.row(F(f, 0)).head<3>(), b = P.row(F(f, 1)).head<3>(), c = P.row(F(f, 2)).head<3>();
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      const double norm = normal.norm();
      if (!(norm > 0) || std::abs(normal.dot(Eigen::Vector3d(P.row(far).head<3>()) - a)) > bend * norm) return false;
    }
  }
  return true;
}

// A tet whose volume is at least this fraction of its longest edge cubed
// (times 6: the generalised cross product's norm) has a hyperplane its
// corners determine: moving them by e (of its size) turns it by at most
// about e / kWellShaped.
constexpr double kWellShaped = 1e-5;

// The distance of `p` from the hyperplane through the tet `tet` (rows of P
// in R^4), or infinity for a tet too flat to have a well-determined one.
double distance_from_hyperplane(const PointMatrix& P, const std::array<Index, 4>& tet, Index p) {
  Eigen::Matrix<double, 3, 4> edges;
  for (int r = 0; r < 3; ++r) edges.row(r) = P.row(tet[r + 1]) - P.row(tet[0]);
  Eigen::Vector4d normal;  // the generalised cross product of the three edges
  for (int column = 0; column < 4; ++column) {
    Eigen::Matrix3d minor;
    for (int c = 0, k = 0; c < 4; ++c)
      if (c != column) minor.col(k++) = edges.col(c);
    normal(column) = (column % 2 ? -1.0 : 1.0) * minor.determinant();
  }
  // A sliver's hyperplane is not determined by its rounded corners (parallel
  // edges of both inputs make such tets): not trusted to say what is flat.
  double longest = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (P.row(tet[a]) - P.row(tet[b])).norm());
  const double norm = normal.norm();
  if (!(norm > kWellShaped * std::pow(longest, 3))) return std::numeric_limits<double>::infinity();
  return std::abs(normal.dot((P.row(p) - P.row(tet[0])).transpose())) / norm;
}

// Whether the surface encloses its hull once: its enclosed volume (by the
// divergence theorem) that of the star of its faces from the interior point
// `inside` (an input wound twice encloses twice the hull's).
bool encloses_its_hull_once(const PointMatrix& P, const SimplexMatrix& F, const Eigen::Vector3d& inside) {
  double star = 0, enclosed = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = P.row(F(f, 0)).head<3>(), b = P.row(F(f, 1)).head<3>(), c = P.row(F(f, 2)).head<3>();
    enclosed += a.dot(b.cross(c)) / 6;
    star += std::abs((a - inside).dot((b - a).cross(c - a))) / 6;
  }
  return enclosed > 0 && std::abs(star - enclosed) <= 1e-9 * enclosed;
}

struct UnionFind {
  std::vector<Index> parent;
  explicit UnionFind(Index n) : parent(static_cast<size_t>(n)) { std::iota(parent.begin(), parent.end(), Index{0}); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(Index a, Index b) { parent[find(a)] = find(b); }
};

// convex_hull_fill's steps, each false when the inputs are not the case it
// handles (the caller then fills otherwise). Points are added in one order
// (the caps' centres, the ridges' middles, the lateral facets' centres, the
// hull's centre): their rows are the result's.
class ConvexFillBuilder {
 public:
  ConvexFillBuilder(const PointMatrix& P, Index nS, const SimplexMatrix& FS, const SimplexMatrix& FT)
      : P_(P), nS_(nS), FS_(FS), FT_(FT), n_(P.rows()), facets_(0) {}

  // Every point is a vertex of one input, each input is convex and encloses
  // its own hull once from its centre (added here, in its plane exactly).
  bool inputs_fit() {
    std::vector<Index> source_vertices(FS_.data(), FS_.data() + FS_.size());
    std::vector<Index> target_vertices(FT_.data(), FT_.data() + FT_.size());
    for (auto* list : {&source_vertices, &target_vertices}) {
      std::sort(list->begin(), list->end());
      list->erase(std::unique(list->begin(), list->end()), list->end());
    }
    if (static_cast<Index>(source_vertices.size() + target_vertices.size()) != n_) return false;  // unused points
    if (!is_convex_at_every_edge(P_, FS_) || !is_convex_at_every_edge(P_, FT_)) return false;
    source_centre_ = add(centre_of(source_vertices)), target_centre_ = add(centre_of(target_vertices));
    added_[0](3) = P_(source_vertices[0], 3), added_[1](3) = P_(target_vertices[0], 3);  // in their planes exactly
    return encloses_its_hull_once(P_, FS_, added_[0].head<3>().transpose()) &&
           encloses_its_hull_once(P_, FT_, added_[1].head<3>().transpose());
  }

  // The hull's boundary, triangulated by an exact Delaunay triangulation of
  // the points, and its facets: boundary tets grouped across the triangles
  // where the next one lies in the same hyperplane, exactly or up to
  // rounding (kRoundingBend).
  bool group_facets() {
    delaunay_ = delaunay_exact(P_);
    boundary_ = boundary_facets(delaunay_.simplices);
    const Index B = boundary_.rows();
    for (Index b = 0; b < B; ++b)
      for (int drop = 0; drop < 4; ++drop) {
        Triangle t;
        for (int c = 0, j = 0; c < 4; ++c)
          if (c != drop) t[j++] = boundary_(b, c);
        tets_of_triangle_[sorted(t)].push_back(b);
      }
    facets_ = UnionFind(B);
    const double flat = kRoundingBend * size_of(P_, 4);
    for (const auto& [triangle, tets] : tets_of_triangle_) {
      if (tets.size() != 2) return false;  // not a closed boundary
      const Index opposite = opposite_of(triangle, tets[1]), other_opposite = opposite_of(triangle, tets[0]);
      const std::array<Index, 5> five{boundary_(tets[0], 0), boundary_(tets[0], 1), boundary_(tets[0], 2),
                                      boundary_(tets[0], 3), opposite};
      if (orientation4(P_, five) == CGAL::ZERO ||
          (distance_from_hyperplane(P_, {five[0], five[1], five[2], five[3]}, opposite) <= flat &&
           distance_from_hyperplane(P_, {boundary_(tets[1], 0), boundary_(tets[1], 1), boundary_(tets[1], 2),
                                         boundary_(tets[1], 3)},
                                    other_opposite) <= flat))
        facets_.unite(tets[0], tets[1]);
    }
    for (Index b = 0; b < B; ++b)
      for (int c = 0; c < 4; ++c) points_of_facet_[facets_.find(b)].insert(boundary_(b, c));
    return true;
  }

  // The 2D faces between facets, each as the Delaunay triangles it holds,
  // then triangulated once for both of its facets: by the input's own
  // triangles where it lies in an end plane, as a star from a point inside
  // it otherwise.
  bool triangulate_ridges() {
    std::map<std::pair<Index, Index>, std::vector<Triangle>> ridge_triangles;  // (smaller root, larger root)
    for (const auto& [triangle, tets] : tets_of_triangle_) {
      const Index f = facets_.find(tets[0]), g = facets_.find(tets[1]);
      if (f != g) ridge_triangles[{std::min(f, g), std::max(f, g)}].push_back(triangle);
    }
    for (const auto& [pair, triangles] : ridge_triangles) {
      std::set<Index> points;
      double area = 0;
      for (const Triangle& t : triangles)
        points.insert(t.begin(), t.end()), area += triangle_area(at(t[0]), at(t[1]), at(t[2]));
      std::vector<Triangle> out;
      if (!triangulate_ridge(pair, triangles, points, out)) return false;
      double covered = 0;
      for (const Triangle& t : out) covered += triangle_area(at(t[0]), at(t[1]), at(t[2]));
      if (!(std::abs(covered - area) <= 1e-9 * area)) return false;  // not the same polygon
      ridge_triangulation_[pair] = std::move(out);
    }
    return true;
  }

  // Each lateral facet that is not a simplex as the star of its ridges'
  // triangles from its centre, each cap as the star of its input's faces from
  // its centre, the whole as the star of all of it from the hull's centre:
  // stars from interior points triangulate a convex polytope whatever its
  // boundary's triangulation (a pulling from a vertex would have to agree
  // with the inputs' triangles on the faces through that vertex).
  bool star_facets() {
    for (const auto& [facet, points] : points_of_facet_) {
      if (is_cap(facet, true) || is_cap(facet, false)) continue;
      if (points.size() == 4) {  // a simplex: itself
        boundary_tets_.push_back({});
        std::copy(points.begin(), points.end(), boundary_tets_.back().begin());
        continue;
      }
      std::vector<Triangle> triangles;
      for (const auto& [pair, ridge] : ridge_triangulation_)
        if (pair.first == facet || pair.second == facet) triangles.insert(triangles.end(), ridge.begin(), ridge.end());
      // Halfway between the centres of its faces in the two planes (inside
      // it), at exactly half the span: every facet's centre at one time, so
      // the frames change topology there only (one cut for live playback).
      const std::optional<Index> centre = middle_between_planes(points);
      if (!centre) return false;  // not between the planes
      star(*centre, triangles);
    }
    star(source_centre_, faces_of(FS_));
    star(target_centre_, faces_of(FT_));
    return true;
  }

  // The stars from the hull's centre, oriented positively; nullopt when one
  // is flat, when they do not fill the hull (their volume that of the
  // Delaunay triangulation, less what facets bent by rounding cut off: 1.3e-8
  // of it for a cylinder whose rotated coordinates were stored in float32),
  // or when they are not a triangulated ball (oriented, its boundary a
  // closed oriented 3-manifold: faces that did not meet up would show as
  // non-manifold triangles in the frames).
  std::optional<ConvexFill> assemble() {
    std::vector<Index> everything(static_cast<size_t>(n_));
    std::iota(everything.begin(), everything.end(), Index{0});
    const Index centre = add(centre_of(everything));
    ConvexFill result;
    result.points.resize(n_ + static_cast<Index>(added_.size()), 4);
    result.points.topRows(n_) = P_;
    for (size_t a = 0; a < added_.size(); ++a) result.points.row(n_ + static_cast<Index>(a)) = added_[a];
    result.source_centre = source_centre_;
    result.target_centre = target_centre_;
    const PointMatrix& Q = result.points;
    result.simplices.resize(static_cast<Index>(boundary_tets_.size()), 5);
    double volume = 0, hull_volume = 0;
    for (size_t s = 0; s < boundary_tets_.size(); ++s) {
      const Tet& tet = boundary_tets_[s];
      std::array<Index, 5> ids{centre, tet[0], tet[1], tet[2], tet[3]};
      const CGAL::Orientation sign = orientation4(Q, ids);
      if (sign == CGAL::ZERO) return std::nullopt;
      if (sign == CGAL::NEGATIVE) std::swap(ids[3], ids[4]);
      volume += std::abs(determinant4(Q, ids));
      for (int c = 0; c < 5; ++c) result.simplices(static_cast<Index>(s), c) = ids[c];
    }
    for (Index s = 0; s < delaunay_.simplices.rows(); ++s) {
      std::array<Index, 5> ids;
      for (int c = 0; c < 5; ++c) ids[c] = delaunay_.simplices(s, c);
      hull_volume += std::abs(determinant4(P_, ids));
    }
    if (!(std::abs(volume - hull_volume) <= kRoundingBend * hull_volume)) return std::nullopt;
    if (!check_manifold(result.simplices).is_oriented_manifold()) return std::nullopt;
    const ManifoldReport surface = check_manifold(boundary_facets(result.simplices));
    if (!surface.is_oriented_manifold() || surface.boundary_facets != 0) return std::nullopt;
    return result;
  }

 private:
  Index add(const Eigen::RowVector4d& p) {
    added_.push_back(p);
    return n_ + static_cast<Index>(added_.size()) - 1;
  }
  Eigen::RowVector4d centre_of(const std::vector<Index>& ids) const {
    Eigen::RowVector4d c = Eigen::RowVector4d::Zero();
    for (const Index v : ids) c += P_.row(v);
    return Eigen::RowVector4d(c / static_cast<double>(ids.size()));
  }
  Eigen::RowVector4d at(Index v) const {
    return v < n_ ? Eigen::RowVector4d(P_.row(v)) : added_[static_cast<size_t>(v - n_)];
  }
  // The corner of boundary tet `b` that is not on `triangle`.
  Index opposite_of(const Triangle& triangle, Index b) const {
    Index opposite = -1;
    for (int c = 0; c < 4; ++c)
      if (std::find(triangle.begin(), triangle.end(), boundary_(b, c)) == triangle.end()) opposite = boundary_(b, c);
    return opposite;
  }
  bool is_cap(Index facet, bool source) const {
    const std::set<Index>& points = points_of_facet_.at(facet);
    return source ? *points.rbegin() < nS_ : *points.begin() >= nS_;
  }
  // A point halfway between the centres of `points`' sides in the two
  // planes, at exactly half the span (added); nullopt when they are not
  // between the planes.
  std::optional<Index> middle_between_planes(const std::set<Index>& points) {
    std::vector<Index> bottom, top;
    for (const Index v : points) (v < nS_ ? bottom : top).push_back(v);
    if (bottom.empty() || top.empty()) return std::nullopt;
    Eigen::RowVector4d centre = 0.5 * (centre_of(bottom) + centre_of(top));
    centre(3) = 0.5 * P_(top[0], 3);
    return add(centre);
  }

  bool triangulate_ridge(const std::pair<Index, Index>& pair, const std::vector<Triangle>& triangles,
                         const std::set<Index>& points, std::vector<Triangle>& out) {
    const bool source_cap_ridge = is_cap(pair.first, true) || is_cap(pair.second, true);
    const bool target_cap_ridge = is_cap(pair.first, false) || is_cap(pair.second, false);
    if (source_cap_ridge || target_cap_ridge) {
      const SimplexMatrix& F = source_cap_ridge ? FS_ : FT_;
      for (Index f = 0; f < F.rows(); ++f)
        if (points.count(F(f, 0)) && points.count(F(f, 1)) && points.count(F(f, 2)))
          out.push_back({F(f, 0), F(f, 1), F(f, 2)});
      return true;
    }
    // A facet that is a simplex is itself (star_facets), so its ridges are
    // its own triangles: a sliver of a side bent by rounding (the trapezoid
    // between the parallel faces of a shape and its scaled copy) keeps the
    // diagonal the Delaunay triangulation gave it.
    if (points.size() == 3 || points_of_facet_.at(pair.first).size() == 4 ||
        points_of_facet_.at(pair.second).size() == 4) {
      out = triangles;
      return true;
    }
    // The star of its boundary edges from a point inside it: pulling from a
    // vertex would span the points on that vertex's own sides (a subdivided
    // cube's edge midpoints) with one edge, and the next face would not meet
    // it there.
    std::map<std::pair<Index, Index>, int> edge_count;
    for (const Triangle& t : triangles)
      for (int i = 0; i < 3; ++i) ++edge_count[std::minmax(t[i], t[(i + 1) % 3])];
    const std::optional<Index> middle = middle_between_planes(points);
    if (!middle) return false;  // not between the planes
    for (const auto& [edge, count] : edge_count)
      if (count == 1) out.push_back({*middle, edge.first, edge.second});
    return true;
  }

  void star(Index centre, const std::vector<Triangle>& triangles) {
    for (const Triangle& t : triangles) boundary_tets_.push_back({centre, t[0], t[1], t[2]});
  }
  static std::vector<Triangle> faces_of(const SimplexMatrix& F) {
    std::vector<Triangle> out;
    for (Index f = 0; f < F.rows(); ++f) out.push_back({F(f, 0), F(f, 1), F(f, 2)});
    return out;
  }

  const PointMatrix& P_;
  Index nS_;
  const SimplexMatrix &FS_, &FT_;
  Index n_;
  std::vector<Eigen::RowVector4d> added_;  // the points added, after P's
  Index source_centre_ = -1, target_centre_ = -1;
  DelaunayTriangulation delaunay_;
  SimplexMatrix boundary_;
  std::map<Triangle, std::vector<Index>> tets_of_triangle_;
  UnionFind facets_;
  std::map<Index, std::set<Index>> points_of_facet_;  // by the facet's root
  std::map<std::pair<Index, Index>, std::vector<Triangle>> ridge_triangulation_;
  std::vector<Tet> boundary_tets_;
};

}  // namespace

std::optional<ConvexFill> convex_hull_fill(const PointMatrix& P, Index nS, const SimplexMatrix& FS,
                                           const SimplexMatrix& FT) {
  if (P.cols() != 4 || FS.rows() < 4 || FT.rows() < 4) return std::nullopt;
  ConvexFillBuilder fill(P, nS, FS, FT);
  if (!fill.inputs_fit() || !fill.group_facets() || !fill.triangulate_ridges() || !fill.star_facets())
    return std::nullopt;
  return fill.assemble();
}

}  // namespace animanifold
