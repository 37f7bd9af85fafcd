// Points on the input surface for refined constraint faces that are not
// Delaunay (see conforming_mend.hpp).
#include "animanifold/conforming_mend.hpp"
#include "point_grid.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace animanifold {

namespace {

using Vec = Eigen::Vector3d;
using Edge = std::pair<Index, Index>;  // smaller index first

Edge edge_of(Index a, Index b) { return std::minmax(a, b); }

Vec row(const PointMatrix& P, Index i) { return P.row(i).transpose(); }

constexpr double kInf = std::numeric_limits<double>::infinity();

// The centre of the circle through a, b, c (in their plane).
Vec circumcentre(const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, n = ab.cross(ac);
  return a + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2 * n.squaredNorm());
}

// Barycentric coordinates of x's projection onto the plane of triangle abc
// (all -inf for a flat triangle, which holds nothing).
std::array<double, 3> barycentric(const Vec& a, const Vec& b, const Vec& c, const Vec& x) {
  const Vec n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  if (!(area > 0)) return {-kInf, -kInf, -kInf};
  const double wa = (c - b).cross(x - b).dot(n) / area, wb = (a - c).cross(x - c).dot(n) / area;
  return {wa, wb, 1.0 - wa - wb};
}

double smallest(const std::array<double, 3>& w) { return std::min({w[0], w[1], w[2]}); }

// How close to an edge a circumcentre may lie and still be inserted inside a
// piece: closer, TetGen's triangulation of that facet would have to place a
// vertex within roundoff of its boundary, so the edge is split instead.
constexpr double kInnerMargin = 0.05;

// The pieces each parent (input triangle) of the bad faces is refined into,
// and the boundary of their union: the edges that occur once among a
// parent's pieces (pieces of input edges, segments to TetGen); edges inside
// the parent occur twice.
class ParentPieces {
 public:
  ParentPieces(const ConstraintSurface& surface, const std::vector<Index>& bad) : faces_(surface.faces) {
    for (const Index s : bad) pieces_.emplace(surface.parent[s], std::vector<Index>{});
    for (Index f = 0; f < static_cast<Index>(faces_.size()); ++f)
      if (const auto it = pieces_.find(surface.parent[f]); it != pieces_.end()) it->second.push_back(f);
  }

  const std::vector<Index>& pieces(Index parent) const { return pieces_.at(parent); }

  const std::vector<Edge>& boundary(Index parent) {
    auto [known, inserted] = boundaries_.try_emplace(parent);
    if (inserted) {
      std::map<Edge, int> uses;
      for (const Index f : pieces_.at(parent))
        for (int i = 0; i < 3; ++i) ++uses[edge_of(faces_[f][i], faces_[f][(i + 1) % 3])];
      for (const auto& [e, count] : uses)
        if (count == 1) known->second.push_back(e);
    }
    return known->second;
  }

 private:
  const std::vector<std::array<Index, 3>>& faces_;
  std::map<Index, std::vector<Index>> pieces_;
  std::map<Index, std::vector<Edge>> boundaries_;
};

// Where the points go that mend the bad faces: edges to split (at the
// point given) and circumcentres to insert inside a piece.
struct MendPlan {
  std::map<Edge, Vec> split;
  std::vector<std::pair<Index, Vec>> centres;  // (piece, circumcentre)
};

// Chooses the point mending bad face s, whose circumcentre is c.
void plan_face(const ConstraintSurface& surface, ParentPieces& parents, Index s, const Vec& c, MendPlan& plan) {
  const PointMatrix& P = surface.points;
  const auto& faces = surface.faces;
  auto corner = [&](Index f, int i) { return row(P, faces[f][i]); };
  auto split_at_midpoint = [&](const Edge& e) { plan.split.emplace(e, 0.5 * (row(P, e.first) + row(P, e.second))); };
  const Index parent = surface.parent[s];
  const std::vector<Edge>& boundary = parents.boundary(parent);

  // A point in a segment's diametral ball would make it non-Delaunay in
  // turn: split the segment instead (Ruppert's rule).
  bool encroaches = false;
  for (const Edge& e : boundary) {
    const Vec a = row(P, e.first), b = row(P, e.second);
    if ((c - 0.5 * (a + b)).squaredNorm() < 0.25 * (b - a).squaredNorm()) {
      split_at_midpoint(e);
      encroaches = true;
    }
  }
  if (encroaches) return;

  // The piece of the parent that holds c best.
  Index holder = -1;
  std::array<double, 3> w{};
  for (const Index f : parents.pieces(parent)) {
    const auto wf = barycentric(corner(f, 0), corner(f, 1), corner(f, 2), c);
    if (holder < 0 || smallest(wf) > smallest(w)) holder = f, w = wf;
  }
  if (smallest(w) < 0) {
    // Outside the input triangle, in no diametral ball: the boundary piece
    // nearest c, which the face's circumcircle reaches over.
    double nearest = kInf;
    const Edge* pick = nullptr;
    for (const Edge& e : boundary) {
      const double d = (c - 0.5 * (row(P, e.first) + row(P, e.second))).squaredNorm();
      if (d < nearest) nearest = d, pick = &e;
    }
    if (pick) split_at_midpoint(*pick);
    return;
  }
  if (smallest(w) < kInnerMargin) {
    const int i = static_cast<int>(std::min_element(w.begin(), w.end()) - w.begin());
    const Edge e = edge_of(faces[holder][(i + 1) % 3], faces[holder][(i + 2) % 3]);
    if (std::find(boundary.begin(), boundary.end(), e) != boundary.end()) {
      split_at_midpoint(e);
    } else {
      // An edge between two pieces of the parent: TetGen merges the pieces
      // into one facet, so this edge constrains nothing and can take the
      // point where c projects onto it.
      const Vec a = row(P, e.first), b = row(P, e.second);
      const double t = std::clamp((c - a).dot(b - a) / (b - a).squaredNorm(), 0.1, 0.9);
      plan.split.emplace(e, a + t * (b - a));
    }
    return;
  }
  plan.centres.emplace_back(holder, c);
}

// TetGen takes points a few 1e-9 of their bounding box's diagonal apart for
// one: it merges them and numbers its output without the second, and its
// points no longer match ours. Two bad faces of nearly one circle (a
// cylinder's cocircular cap) ask for circumcentres 2e-8 apart; a flat cell's
// diagonal can be split next to one. No point is planned within this share
// of the diagonal of one there, well clear of TetGen's tolerance.
constexpr double kCoincident = 1e-6;

// The points of a surface and those planned for it so far, to find a
// planned point that would coincide with one.
class CoincidentPoints {
 public:
  explicit CoincidentPoints(const PointMatrix& P)
      : grid_(std::max(kCoincident * (P.rows() ? (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm() : 0.0),
                       std::numeric_limits<double>::min())) {
    for (Index r = 0; r < P.rows(); ++r) add(row(P, r));
  }

  bool near(const Vec& x) const {
    bool found = false;
    grid_.near(x, [&found](Index, double) { found = true; });
    return found;
  }

  void add(const Vec& x) { grid_.add(x, 0); }

 private:
  PointGrid grid_;
};

// The planned points appended to the surface's points (edge points first,
// then circumcentres): the point each split edge takes, and per face its
// inner points. A circumcentre is deferred when its piece is being split.
struct AddedPoints {
  std::map<Edge, Index> split_point;
  std::vector<std::vector<Index>> inner;
};
AddedPoints add_points(ConstraintSurface& surface, const MendPlan& plan, MendReport& report) {
  PointMatrix& P = surface.points;
  const auto& faces = surface.faces;
  AddedPoints out;
  Index next = static_cast<Index>(P.rows());
  std::vector<Vec> added;
  CoincidentPoints taken(P);
  for (const auto& [e, at] : plan.split) {
    if (taken.near(at)) continue;  // the edge stays whole: both faces beside it see no split
    out.split_point.emplace(e, next++), added.push_back(at), taken.add(at);
  }
  std::set<Index> splitting;
  for (Index f = 0; f < static_cast<Index>(faces.size()); ++f)
    for (int i = 0; i < 3; ++i)
      if (out.split_point.count(edge_of(faces[f][i], faces[f][(i + 1) % 3]))) splitting.insert(f);
  out.inner = surface.inner;
  out.inner.resize(faces.size());
  for (const auto& [f, c] : plan.centres) {
    if (splitting.count(f)) {
      ++report.deferred;
      continue;
    }
    // Faces that share a circumcircle (cocircular corners) ask for one point.
    if (taken.near(c)) continue;
    out.inner[f].push_back(next++);
    added.push_back(c), taken.add(c);
    ++report.inner_points;
  }
  report.edge_points = static_cast<Index>(out.split_point.size());
  const Index old_rows = static_cast<Index>(P.rows());
  P.conservativeResize(next, 3);
  for (size_t k = 0; k < added.size(); ++k) P.row(old_rows + static_cast<Index>(k)) = added[k].transpose();
  return out;
}

// Splits every triangle along its split edges (orientation kept), one edge
// at a time; inner points follow the half that holds them best.
void split_faces(ConstraintSurface& surface, AddedPoints& added) {
  const PointMatrix& P = surface.points;
  const auto& faces = surface.faces;
  std::vector<std::array<Index, 3>> out_faces;
  std::vector<Index> out_parent;
  std::vector<std::vector<Index>> out_inner;
  struct Piece {
    std::array<Index, 3> tri;
    std::vector<Index> inner;
  };
  std::vector<Piece> stack;
  for (Index f = 0; f < static_cast<Index>(faces.size()); ++f) {
    stack.push_back({faces[f], std::move(added.inner[f])});
    while (!stack.empty()) {
      Piece piece = std::move(stack.back());
      stack.pop_back();
      int at = -1;
      for (int i = 0; i < 3 && at < 0; ++i)
        if (added.split_point.count(edge_of(piece.tri[i], piece.tri[(i + 1) % 3]))) at = i;
      if (at < 0) {
        out_faces.push_back(piece.tri);
        out_parent.push_back(surface.parent[f]);
        out_inner.push_back(std::move(piece.inner));
        continue;
      }
      const Index a = piece.tri[at], b = piece.tri[(at + 1) % 3], c = piece.tri[(at + 2) % 3];
      const Index m = added.split_point.at(edge_of(a, b));
      Piece first{{a, m, c}, {}}, second{{m, b, c}, {}};
      for (const Index p : piece.inner) {
        const Vec x = row(P, p);
        const double in_first = smallest(barycentric(row(P, a), row(P, m), row(P, c), x));
        const double in_second = smallest(barycentric(row(P, m), row(P, b), row(P, c), x));
        (in_first >= in_second ? first : second).inner.push_back(p);
      }
      stack.push_back(std::move(first));
      stack.push_back(std::move(second));
    }
  }
  surface.faces = std::move(out_faces);
  surface.parent = std::move(out_parent);
  surface.inner = std::move(out_inner);
}

}  // namespace

MendReport mend_non_delaunay_faces(ConstraintSurface& surface, const std::vector<Index>& bad) {
  MendReport report;
  const PointMatrix& P = surface.points;
  const auto& faces = surface.faces;
  ParentPieces parents(surface, bad);
  MendPlan plan;
  for (const Index s : bad) {
    const Vec c = circumcentre(row(P, faces[s][0]), row(P, faces[s][1]), row(P, faces[s][2]));
    if (!c.allFinite()) continue;  // a flat face: nothing sensible to add
    plan_face(surface, parents, s, c, plan);
  }
  AddedPoints added = add_points(surface, plan, report);
  split_faces(surface, added);
  return report;
}

FlatCells flat_surface_cells(const SimplexMatrix& tets, const PointMatrix& points, const SimplexMatrix& faces) {
  constexpr double kFlat = 1e-9;
  std::vector<bool> on_surface(static_cast<size_t>(points.rows()), false);
  std::set<Edge> surface_edges;
  for (Index f = 0; f < faces.rows(); ++f)
    for (int i = 0; i < 3; ++i) {
      on_surface[faces(f, i)] = true;
      surface_edges.insert(edge_of(faces(f, i), faces(f, (i + 1) % 3)));
    }
  FlatCells out;
  std::set<Edge> chosen;
  for (Index t = 0; t < tets.rows(); ++t) {
    const Index* c = tets.row(t).data();
    if (!(on_surface[c[0]] && on_surface[c[1]] && on_surface[c[2]] && on_surface[c[3]])) continue;
    const Vec p0 = row(points, c[0]);
    const Vec e1 = row(points, c[1]) - p0, e2 = row(points, c[2]) - p0, e3 = row(points, c[3]) - p0;
    auto length = [&](int a, int b) { return (row(points, c[a]) - row(points, c[b])).norm(); };
    double longest = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) longest = std::max(longest, length(a, b));
    if (std::abs(e1.dot(e2.cross(e3))) > kFlat * longest * longest * longest) continue;
    ++out.cells;
    // The diagonals cross: of a convex quad's three pairs of opposite edges
    // theirs is the longest in sum (the triangle inequality at the crossing).
    static constexpr int kPairs[3][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}};
    int best = 0;
    for (int p = 1; p < 3; ++p)
      if (length(kPairs[p][0], kPairs[p][1]) + length(kPairs[p][2], kPairs[p][3]) >
          length(kPairs[best][0], kPairs[best][1]) + length(kPairs[best][2], kPairs[best][3]))
        best = p;
    const Edge first = edge_of(c[kPairs[best][0]], c[kPairs[best][1]]);
    const Edge second = edge_of(c[kPairs[best][2]], c[kPairs[best][3]]);
    const bool has_first = surface_edges.count(first) > 0, has_second = surface_edges.count(second) > 0;
    if (!has_first && !has_second) {
      // Four cocircular points in one plane across a step or a hole (inputs
      // on a grid): the cell's sides that are the surface's edges are
      // chords of the circle, and the middle of the longest lies inside
      // every sphere through it, which breaks the tie.
      ++out.without_surface_diagonal;
      Edge side{-1, -1};
      double side_length = 0;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b)
          if (surface_edges.count(edge_of(c[a], c[b])) && length(a, b) > side_length)
            side = edge_of(c[a], c[b]), side_length = length(a, b);
      if (side.first >= 0 && chosen.insert(side).second) out.diagonals.push_back({side.first, side.second});
      continue;
    }
    const Edge diagonal = has_first && (!has_second || length(kPairs[best][0], kPairs[best][1]) >=
                                                          length(kPairs[best][2], kPairs[best][3]))
                              ? first
                              : second;
    if (chosen.insert(diagonal).second) out.diagonals.push_back({diagonal.first, diagonal.second});
  }
  return out;
}

MendReport split_surface_edges(ConstraintSurface& surface, const std::vector<std::array<Index, 2>>& edges) {
  MendReport report;
  std::set<Edge> present;  // an edge the other mending split already is gone
  for (const auto& f : surface.faces)
    for (int i = 0; i < 3; ++i) present.insert(edge_of(f[i], f[(i + 1) % 3]));
  MendPlan plan;
  for (const auto& e : edges)
    if (present.count(edge_of(e[0], e[1])))
      plan.split.emplace(edge_of(e[0], e[1]), 0.5 * (row(surface.points, e[0]) + row(surface.points, e[1])));
  surface.inner.resize(surface.faces.size());
  AddedPoints added = add_points(surface, plan, report);
  split_faces(surface, added);
  return report;
}

}  // namespace animanifold
