// Voronoi separability (§7.5-7.6): input checks, the dihedral-angle test,
// edge/face encroachment and the iterative closest-point splitting.
#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/skeleton.hpp"
#include "skeleton_internal.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <numeric>

namespace animanifold {

using namespace skeleton_detail;

namespace skeleton_detail {

PointGrid::PointGrid(const std::vector<Vec3>& points, double cell) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (points.empty()) lo = hi = Vec3::Zero();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  cell_ = std::max(cell, extent * 1e-6);
  // Keep the dense grid at most a few cells per point.
  const double limit = 4.0 * static_cast<double>(points.size()) + 64.0;
  for (;;) {
    double total = 1;
    for (int k = 0; k < 3; ++k) total *= std::floor((hi[k] - lo[k]) / cell_) + 1;
    if (total <= limit) break;
    cell_ *= 1.25;
  }
  origin_ = lo;
  for (int k = 0; k < 3; ++k) dims_[k] = static_cast<long>(std::floor((hi[k] - lo[k]) / cell_)) + 1;
  const long cells = dims_[0] * dims_[1] * dims_[2];
  std::vector<long> cell_of(points.size());
  start_.assign(static_cast<size_t>(cells) + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    long c[3];
    for (int k = 0; k < 3; ++k)
      c[k] = std::clamp<long>(static_cast<long>(std::floor((points[i][k] - lo[k]) / cell_)), 0, dims_[k] - 1);
    cell_of[i] = (c[2] * dims_[1] + c[1]) * dims_[0] + c[0];
    ++start_[cell_of[i] + 1];
  }
  for (long c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(points.size());
  std::vector<Index> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) items_[fill[cell_of[i]]++] = static_cast<Index>(i);
}

EdgeTable edge_table(const SimplexMatrix& F) {
  struct Half {
    Index a, b, face, apex;
    int slot;
  };
  std::vector<Half> halves;
  halves.reserve(static_cast<size_t>(F.rows()) * 3);
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index u = F(f, k), v = F(f, (k + 1) % 3);
      halves.push_back({std::min(u, v), std::max(u, v), f, F(f, (k + 2) % 3), k});
    }
  std::sort(halves.begin(), halves.end(),
            [](const Half& x, const Half& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  EdgeTable table;
  table.face_edges.assign(static_cast<size_t>(F.rows()), {-1, -1, -1});
  for (size_t i = 0; i < halves.size();) {
    size_t j = i;
    while (j < halves.size() && halves[j].a == halves[i].a && halves[j].b == halves[i].b) ++j;
    const Index e = static_cast<Index>(table.edge.size());
    table.edge.push_back({halves[i].a, halves[i].b});
    table.opposite.push_back({halves[i].apex, j > i + 1 ? halves[i + 1].apex : -1});
    for (size_t h = i; h < j; ++h) table.face_edges[halves[h].face][halves[h].slot] = e;
    i = j;
  }
  return table;
}

std::vector<std::vector<Index>> vertex_neighbours(const SimplexMatrix& F, Index vertex_count) {
  std::vector<std::vector<Index>> out(static_cast<size_t>(vertex_count));
  const int k = static_cast<int>(F.cols());
  for (Index f = 0; f < F.rows(); ++f)
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b)
        if (a != b) out[F(f, a)].push_back(F(f, b));
  for (auto& n : out) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return out;
}

}  // namespace skeleton_detail

// ------------------------------------------------------------------- checks

namespace {

// Columns, faces that repeat a vertex, vertices no face uses.
void check_faces_and_vertices(const PointMatrix& V, const SimplexMatrix& F) {
  const int D = static_cast<int>(V.cols());
  if (D != 2 && D != 3)
    fail<InputError>("the Voronoi skeleton needs vertices in R^2 or R^3, got ", D, " columns");
  if (F.cols() != D)
    fail<InputError>(D == 2 ? "a polygon in R^2 is given by segments (2 columns)"
                            : "a mesh in R^3 is given by triangles (3 columns)",
                     ", got ", F.cols(), " columns");
  if (F.rows() == 0) fail<InputError>("the mesh has no faces");
  {
    Complex c;
    c.V = V;
    c.S = F;
    c.validate();
  }
  const char* face_word = D == 2 ? "segment" : "face";
  for (Index f = 0; f < F.rows(); ++f)
    for (int a = 0; a < D; ++a)
      for (int b = a + 1; b < D; ++b)
        if (F(f, a) == F(f, b)) fail<InputError>(face_word, " ", f, " repeats vertex ", F(f, a));
  std::vector<int> used(static_cast<size_t>(V.rows()), 0);
  for (Index f = 0; f < F.rows(); ++f)
    for (int a = 0; a < D; ++a) ++used[F(f, a)];
  for (Index v = 0; v < V.rows(); ++v)
    if (!used[v]) fail<InputError>("vertex ", v, " is not used by any ", face_word, " (remove unused vertices)");
}

// The faces' adjacency, every facet with a neighbour.
FacetAdjacency closed_adjacency(const SimplexMatrix& F) {
  const int D = static_cast<int>(F.cols());
  FacetAdjacency adjacency;
  try {
    adjacency = facet_adjacency(F);
  } catch (const InputError& e) {
    fail<InputError>("the ", D == 2 ? "polygon" : "mesh", " is non-manifold: ", e.what());
  }
  for (Index f = 0; f < F.rows(); ++f)
    for (int i = 0; i < D; ++i)
      if (adjacency.neighbour(f, i) < 0) {
        if (D == 2)
          fail<InputError>("the polygon is open: vertex ", F(f, 1 - i), " ends segment ", f,
                           " without a continuing segment (the Voronoi skeleton needs closed polygons)");
        fail<InputError>("the mesh is open: edge (", F(f, (i + 1) % 3), ", ", F(f, (i + 2) % 3), ") of face ", f,
                         " has no neighbour (the Voronoi skeleton needs closed meshes)");
      }
  return adjacency;
}

// Triangles: neighbours list their shared edge in opposite orders.
void check_consistent_triangles(const SimplexMatrix& F, const FacetAdjacency& adjacency) {
  for (Index f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) {
      const Index g = adjacency.neighbour(f, i);
      if (g < f) continue;
      Index a[2], b[2];
      facet(F.row(f).data(), 3, i, a);
      facet(F.row(g).data(), 3, adjacency.opposite(f, i), b);
      if (a[0] == b[0])
        fail<InputError>("faces ", f, " and ", g, " are inconsistently oriented across edge (", a[0], ", ", a[1],
                         ")");
    }
}

// Segments: the vertex that ends a segment starts the next one (not ends another).
void check_consistent_segments(const SimplexMatrix& F, const FacetAdjacency& adjacency) {
  for (Index f = 0; f < F.rows(); ++f) {
    const Index g = adjacency.neighbour(f, 0);  // across facet 0 = vertex F(f,1)
    if (F(g, 0) != F(f, 1))
      fail<InputError>("segments ", f, " and ", g, " are inconsistently oriented at vertex ", F(f, 1));
  }
}

// Manifold vertices: the faces around each vertex form one fan.
void check_vertex_fans(Index vertex_count, const SimplexMatrix& F, const FacetAdjacency& adjacency) {
  const VertexStar star = vertex_star(F, vertex_count);
  for (Index v = 0; v < vertex_count; ++v) {
    const Index first = star.simplices[star.offsets[v]];
    Index f = first, steps = 0;
    do {
      int k = 0;
      while (F(f, k) != v) ++k;
      f = adjacency.neighbour(f, (k + 2) % 3);  // across edge (v, next)
      ++steps;
    } while (f != first && steps <= star.offsets[v + 1] - star.offsets[v]);
    if (steps != star.offsets[v + 1] - star.offsets[v])
      fail<InputError>("the mesh is non-manifold at vertex ", v, ": its ", star.offsets[v + 1] - star.offsets[v],
                       " faces form more than one fan");
  }
}

// Coincident vertices would share one Voronoi cell.
void check_distinct_vertices(const PointMatrix& V) {
  const int D = static_cast<int>(V.cols());
  std::vector<Index> order(static_cast<size_t>(V.rows()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) {
    for (int c = 0; c < D; ++c)
      if (V(a, c) != V(b, c)) return V(a, c) < V(b, c);
    return a < b;
  });
  for (size_t i = 1; i < order.size(); ++i)
    if ((V.row(order[i]) - V.row(order[i - 1])).squaredNorm() == 0)
      fail<InputError>("vertices ", std::min(order[i], order[i - 1]), " and ", std::max(order[i], order[i - 1]),
                       " coincide");
}

// Outward orientation: positive enclosed area / volume.
void check_outward(const PointMatrix& V, const SimplexMatrix& F) {
  const int D = static_cast<int>(V.cols());
  double measure = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    if (D == 2) {
      measure += V(F(f, 0), 0) * V(F(f, 1), 1) - V(F(f, 1), 0) * V(F(f, 0), 1);
    } else {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      measure += a.dot(b.cross(c));
    }
  }
  if (!(measure > 0))
    fail<InputError>("the ", D == 2 ? "polygon" : "mesh", " is oriented inward (enclosed ", D == 2 ? "area " : "volume ",
                     measure / (D == 2 ? 2 : 6), " <= 0): reverse its ", D == 2 ? "segment" : "face", "s");
}

}  // namespace

void check_closed_oriented(const PointMatrix& V, const SimplexMatrix& F) {
  check_faces_and_vertices(V, F);
  const FacetAdjacency adjacency = closed_adjacency(F);
  if (V.cols() == 3) {
    check_consistent_triangles(F, adjacency);
    check_vertex_fans(static_cast<Index>(V.rows()), F, adjacency);
  } else {
    check_consistent_segments(F, adjacency);
  }
  check_distinct_vertices(V);
  check_outward(V, F);
}

// ----------------------------------------------------------- dihedral test

DihedralReport dihedral_test(const PointMatrix& V, const SimplexMatrix& F, double limit) {
  check_closed_oriented(V, F);
  DihedralReport report;
  report.limit = limit;
  std::vector<Index> where;
  std::vector<double> angles;
  const int D = static_cast<int>(V.cols());
  if (D == 2) {
    const FacetAdjacency adjacency = facet_adjacency(F);
    for (Index f = 0; f < F.rows(); ++f) {
      const Index g = adjacency.neighbour(f, 0);  // the segment starting at F(f,1)
      const Eigen::Vector2d v = V.row(F(f, 1)), prev = V.row(F(f, 0)), next = V.row(F(g, 1));
      const Eigen::Vector2d a = (prev - v).normalized(), b = (next - v).normalized();
      const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
      report.sharpest = std::min(report.sharpest, angle);
      if (angle < limit) {
        where.push_back(F(f, 1));
        angles.push_back(angle);
      }
    }
    report.sharp.resize(static_cast<Index>(where.size()), 1);
  } else {
    const EdgeTable edges = edge_table(F);
    std::vector<Eigen::Vector3d> normal(static_cast<size_t>(F.rows()));
    for (Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      normal[f] = (b - a).cross(c - a).normalized();
    }
    std::vector<std::array<Index, 2>> faces_of(edges.edge.size(), {-1, -1});
    for (Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        auto& slot = faces_of[edges.face_edges[f][k]];
        (slot[0] < 0 ? slot[0] : slot[1]) = f;
      }
    for (size_t e = 0; e < edges.edge.size(); ++e) {
      const double cosine = std::clamp(normal[faces_of[e][0]].dot(normal[faces_of[e][1]]), -1.0, 1.0);
      const double angle = M_PI - std::acos(cosine);
      report.sharpest = std::min(report.sharpest, angle);
      if (angle < limit) {
        where.push_back(edges.edge[e][0]);
        where.push_back(edges.edge[e][1]);
        angles.push_back(angle);
      }
    }
    report.sharp.resize(static_cast<Index>(angles.size()), 2);
  }
  std::copy(where.begin(), where.end(), report.sharp.data());
  report.angles = Eigen::Map<Eigen::VectorXd>(angles.data(), static_cast<Index>(angles.size()));
  report.passes = angles.empty();
  return report;
}

// ------------------------------------------------------------ encroachment

namespace {

constexpr double kStrict = 1e-9;  // relative margin: points on a sphere do not encroach

void check_rule(const EncroachmentRule& rule) {
  if (rule.neighbourhood != 1 && rule.neighbourhood != 2)
    fail<InputError>("neighbourhood must be 1 or 2, got ", rule.neighbourhood);
  if (!(rule.in_plane_angle >= 0 && rule.in_plane_angle < M_PI / 2))
    fail<InputError>("in_plane_angle must be in [0, pi/2) radians, got ", rule.in_plane_angle);
}

struct Encroached {
  bool face;        // false: edge (segment)
  Index simplex;    // edge index (3D), segment/face row
  Index vertex;
  double distance;
  Vec3 point;       // the closest point of the simplex to the vertex: where to split
  int type;
};

// The closest encroachers of a mesh's edges (segments) and faces under an
// encroachment rule: one method per kind of test.
class EncroachmentSearch {
 public:
  EncroachmentSearch(const std::vector<Vec3>& P, const SimplexMatrix& F, int D, const EdgeTable* edges,
                     const EncroachmentRule& rule)
      : P_(P), F_(F), D_(D), edges_(edges),
        in_plane_sine_(rule.in_plane_angle > 0 ? std::sin(rule.in_plane_angle) : 0.0),
        edge_count_(D == 2 ? F.rows() : static_cast<Index>(edges->edge.size())),
        grid_(P, mean_edge_length()) {
    if (D == 3 && rule.neighbourhood >= 2) adjacent_ = vertex_neighbours(F, static_cast<Index>(P.size()));
  }

  Index edge_count() const { return edge_count_; }

  // Edge (diametral sphere) encroachment of edge `e`; one-ring edges skipped in R^3.
  Encroached edge(Index e) const {
    auto [a, b] = edge_ends(e);
    const Vec3 &pa = P_[a], &pb = P_[b];
    const Vec3 mid = 0.5 * (pa + pb);
    const double r = 0.5 * (pb - pa).norm();
    const double margin = kStrict * (pb - pa).squaredNorm();
    Index apex0 = -1, apex1 = -1;
    if (D_ == 3) apex0 = edges_->opposite[e][0], apex1 = edges_->opposite[e][1];
    Encroached best{false, e, -1, std::numeric_limits<double>::max(), Vec3::Zero(), 2};
    grid_.query(mid - Vec3::Constant(r), mid + Vec3::Constant(r), [&](Index p) {
      if (skip_edge(p, a, b, apex0, apex1)) return;
      const Vec3& x = P_[p];
      if ((x - pa).dot(x - pb) >= -margin) return;
      const double t = (x - pa).dot(pb - pa) / (pb - pa).squaredNorm();
      const Vec3 foot = pa + t * (pb - pa);
      const double d = (x - foot).norm();
      if (D_ == 3 && in_plane_sine_ > 0)  // within the surface (§7.6: in-plane degree of freedom)
        for (Index apex : {apex0, apex1}) {
          const Vec3 nf = (pb - pa).cross(P_[apex] - pa).normalized();
          if (std::abs(nf.dot(x - pa)) < in_plane_sine_ * d) return;
        }
      if (d < best.distance || (d == best.distance && p < best.vertex)) {
        best.vertex = p;
        best.distance = d;
        best.point = foot;
      }
    });
    return best;
  }

  // Face (minimum equatorial sphere, above or below the face) encroachment of
  // face `f`, type 4 when the encroacher also encroaches an edge of the face.
  Encroached face(Index f) const {
    const Index ia = F_(f, 0), ib = F_(f, 1), ic = F_(f, 2);
    const Vec3 &a = P_[ia], &b = P_[ib], &c = P_[ic];
    const Vec3 ab = b - a, ac = c - a, n = ab.cross(ac);
    const double n2 = n.squaredNorm();
    Encroached best{true, f, -1, std::numeric_limits<double>::max(), Vec3::Zero(), 3};
    if (n2 == 0) return best;
    const Vec3 centre = a + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2 * n2);
    const double R2 = (centre - a).squaredNorm();
    const double R = std::sqrt(R2);
    const Vec3 unit = n / std::sqrt(n2);
    Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const Vec3 slab = R * unit.cwiseAbs();
    lo = (lo - slab).cwiseMax(centre - Vec3::Constant(R));
    hi = (hi + slab).cwiseMin(centre + Vec3::Constant(R));
    grid_.query(lo, hi, [&](Index p) {
      if (p == ia || p == ib || p == ic) return;
      const Vec3& x = P_[p];
      if ((x - centre).squaredNorm() >= R2 * (1 - kStrict)) return;
      const double h = (x - a).dot(unit);
      const Vec3 q = x - h * unit;
      // Barycentric coordinates of the projection: strictly inside.
      const double wb = (q - a).cross(ac).dot(n) / n2;
      const double wc = ab.cross(q - a).dot(n) / n2;
      const double wa = 1 - wb - wc;
      if (wa <= kStrict || wb <= kStrict || wc <= kStrict) return;
      const double d = std::abs(h);
      if (d < best.distance || (d == best.distance && p < best.vertex)) {
        best.vertex = p;
        best.distance = d;
        best.point = q;
      }
    });
    if (best.vertex >= 0 && encroaches_an_edge_of(f, best.vertex)) best.type = 4;
    return best;
  }

 private:
  std::array<Index, 2> edge_ends(Index e) const {
    if (D_ == 2) return {F_(e, 0), F_(e, 1)};
    return edges_->edge[e];
  }

  double mean_edge_length() const {
    double mean = 0;
    Index count = 0;
    for (Index e = 0; e < edge_count_; ++e, ++count) {
      auto [a, b] = edge_ends(e);
      mean += (P_[a] - P_[b]).norm();
    }
    return mean / std::max<Index>(count, 1);
  }

  // Edge tests skipped in R^3: edges of the vertex's one-ring triangles (neighbourhood 1, the
  // dissertation's rule) or every edge touching its one-ring vertices (neighbourhood 2).
  bool skip_edge(Index p, Index a, Index b, Index apex0, Index apex1) const {
    if (p == a || p == b || p == apex0 || p == apex1) return true;
    if (adjacent_.empty()) return false;
    return std::binary_search(adjacent_[a].begin(), adjacent_[a].end(), p) ||
           std::binary_search(adjacent_[b].begin(), adjacent_[b].end(), p);
  }

  bool encroaches_an_edge_of(Index f, Index vertex) const {
    const Vec3& x = P_[vertex];
    bool any = false;
    for (int k = 0; k < 3; ++k) {
      const Index e = edges_->face_edges[f][k];
      const auto [u, v] = edges_->edge[e];
      if (skip_edge(vertex, u, v, edges_->opposite[e][0], edges_->opposite[e][1])) continue;
      if ((x - P_[u]).dot(x - P_[v]) < -kStrict * (P_[u] - P_[v]).squaredNorm()) any = true;
    }
    return any;
  }

  const std::vector<Vec3>& P_;
  const SimplexMatrix& F_;
  int D_;
  const EdgeTable* edges_;
  double in_plane_sine_;
  Index edge_count_;
  std::vector<std::vector<Index>> adjacent_;
  PointGrid grid_;
};

// The closest encroacher of every encroached edge/segment and face.
std::vector<Encroached> find_encroached(const std::vector<Vec3>& P, const SimplexMatrix& F, int D,
                                        const EdgeTable* edges, const EncroachmentRule& rule) {
  const EncroachmentSearch search(P, F, D, edges, rule);
  std::vector<Encroached> out;
  for (Index e = 0; e < search.edge_count(); ++e)
    if (const Encroached best = search.edge(e); best.vertex >= 0) out.push_back(best);
  if (D == 2) return out;
  for (Index f = 0; f < F.rows(); ++f)
    if (const Encroached best = search.face(f); best.vertex >= 0) out.push_back(best);
  return out;
}

}  // namespace

std::vector<Encroachment> encroachments(const PointMatrix& V, const SimplexMatrix& F, const EncroachmentRule& rule) {
  check_rule(rule);
  check_closed_oriented(V, F);
  const int D = static_cast<int>(V.cols());
  const auto P = to_vec3(V);
  EdgeTable edges;
  if (D == 3) edges = edge_table(F);
  std::vector<Encroachment> out;
  for (const auto& e : find_encroached(P, F, D, D == 3 ? &edges : nullptr, rule)) {
    Encroachment r{e.vertex, -1, -1, -1, e.type, e.distance};
    if (e.face) {
      r.a = F(e.simplex, 0), r.b = F(e.simplex, 1), r.c = F(e.simplex, 2);
    } else if (D == 2) {
      r.a = F(e.simplex, 0), r.b = F(e.simplex, 1);
    } else {
      r.a = edges.edge[e.simplex][0], r.b = edges.edge[e.simplex][1];
    }
    out.push_back(r);
  }
  return out;
}

// -------------------------------------------------------------- splitting

namespace {

// Splits encroached simplices at the given points, keeping the mesh closed,
// conforming and oriented: every face with split edges is re-triangulated
// (1, 2 or 3 split edges), and a face without split edges that is itself
// encroached gets a 1-to-3 split at its point.
//
// This is the local stand-in for chapter 6's barycentric refinement
// (`refine.hpp`, branch `refine`): a split tuple here is (simplex, point),
// with the point the orthogonal projection of the encroacher, i.e. the
// barycentric coordinates of Figure 7.9. Switch to refine's split tuples once
// that branch is merged.
void split_encroached_simplices(std::vector<Vec3>& P, SimplexMatrix& F, int D, const EdgeTable* edges,
                                const std::vector<Encroached>& splits, Index& inserted) {
  if (D == 2) {
    std::vector<Index> at(static_cast<size_t>(F.rows()), -1);
    for (const auto& s : splits) {
      at[s.simplex] = static_cast<Index>(P.size());
      P.push_back(s.point);
      ++inserted;
    }
    std::vector<std::array<Index, 2>> out;
    for (Index f = 0; f < F.rows(); ++f) {
      if (at[f] < 0) {
        out.push_back({F(f, 0), F(f, 1)});
      } else {
        out.push_back({F(f, 0), at[f]});
        out.push_back({at[f], F(f, 1)});
      }
    }
    F.resize(static_cast<Index>(out.size()), 2);
    for (size_t i = 0; i < out.size(); ++i) F(i, 0) = out[i][0], F(i, 1) = out[i][1];
    return;
  }
  std::vector<Index> edge_point(edges->edge.size(), -1), face_point(static_cast<size_t>(F.rows()), -1);
  for (const auto& s : splits)
    if (!s.face) {
      edge_point[s.simplex] = static_cast<Index>(P.size());
      P.push_back(s.point);
      ++inserted;
    }
  for (const auto& s : splits)
    if (s.face) {
      const auto& fe = edges->face_edges[s.simplex];
      if (edge_point[fe[0]] >= 0 || edge_point[fe[1]] >= 0 || edge_point[fe[2]] >= 0) continue;  // next round
      face_point[s.simplex] = static_cast<Index>(P.size());
      P.push_back(s.point);
      ++inserted;
    }
  std::vector<std::array<Index, 3>> out;
  out.reserve(static_cast<size_t>(F.rows()) + 3 * splits.size());
  for (Index f = 0; f < F.rows(); ++f) {
    const Index v[3] = {F(f, 0), F(f, 1), F(f, 2)};
    Index m[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      m[k] = edge_point[edges->face_edges[f][k]];  // on edge v[k] v[k+1]
      count += m[k] >= 0;
    }
    if (count == 0) {
      if (face_point[f] < 0) {
        out.push_back({v[0], v[1], v[2]});
      } else {
        const Index c = face_point[f];
        out.push_back({v[0], v[1], c});
        out.push_back({v[1], v[2], c});
        out.push_back({v[2], v[0], c});
      }
    } else if (count == 1) {
      int k = 0;
      while (m[k] < 0) ++k;
      const Index a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      out.push_back({a, m[k], c});
      out.push_back({m[k], b, c});
    } else if (count == 2) {
      int k = 0;  // the unsplit edge is v[k] v[k+1]; rotate so it is (c, a) below
      while (m[k] >= 0) ++k;
      const Index c = v[k], a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      const Index mab = m[(k + 1) % 3], mbc = m[(k + 2) % 3];
      out.push_back({mab, b, mbc});
      // Quad a, mab, mbc, c: the shorter diagonal.
      if ((P[a] - P[mbc]).squaredNorm() <= (P[mab] - P[c]).squaredNorm()) {
        out.push_back({a, mab, mbc});
        out.push_back({a, mbc, c});
      } else {
        out.push_back({a, mab, c});
        out.push_back({mab, mbc, c});
      }
    } else {
      out.push_back({v[0], m[0], m[2]});
      out.push_back({m[0], v[1], m[1]});
      out.push_back({m[2], m[1], v[2]});
      out.push_back({m[0], m[1], m[2]});
    }
  }
  F.resize(static_cast<Index>(out.size()), 3);
  for (size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < 3; ++k) F(static_cast<Index>(i), k) = out[i][k];
}

}  // namespace

SeparabilityResult make_voronoi_separable(const PointMatrix& V, const SimplexMatrix& F, int max_iterations,
                                          const EncroachmentRule& rule) {
  check_closed_oriented(V, F);
  check_rule(rule);
  if (max_iterations < 0) fail<InputError>("max_iterations must be >= 0, got ", max_iterations);
  const int D = static_cast<int>(V.cols());
  std::vector<Vec3> P = to_vec3(V);
  SeparabilityResult result;
  result.faces = F;
  for (;;) {
    EdgeTable edges;
    if (D == 3) edges = edge_table(result.faces);
    const auto found = find_encroached(P, result.faces, D, D == 3 ? &edges : nullptr, rule);
    if (found.empty()) {
      result.separable = true;
      break;
    }
    if (result.iterations >= max_iterations) {
      result.remaining = static_cast<Index>(found.size());
      break;
    }
    split_encroached_simplices(P, result.faces, D, D == 3 ? &edges : nullptr, found, result.splits);
    ++result.iterations;
  }
  result.vertices.resize(static_cast<Index>(P.size()), D);
  for (size_t i = 0; i < P.size(); ++i)
    for (int c = 0; c < D; ++c) result.vertices(static_cast<Index>(i), c) = P[i][c];
  return result;
}

}  // namespace animanifold
