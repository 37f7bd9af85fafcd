// Topology of the field morph's halves (morph_field_internal.hpp): each
// layer's signs follow the blend's only where a sign change is simple.
#include "morph_field_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

namespace animanifold::morph_field {

namespace {

// Topology changes tried one by one, with the Betti numbers counted again
// after each, per layer at most.
constexpr int kTopologyTries = 64;
// A point held out of the negative region (preserve_topology) keeps this
// many floors above zero.
constexpr double kHeldOutside = 30;

// Vertex-to-tet incidence of a tetrahedralization, compressed.
struct Stars {
  std::vector<Index> offset, tets;
  Stars(const SimplexMatrix& cells, Index vertices) : offset(static_cast<size_t>(vertices) + 1, 0) {
    for (Index c = 0; c < cells.rows(); ++c)
      for (int k = 0; k < 4; ++k) ++offset[cells(c, k) + 1];
    std::partial_sum(offset.begin(), offset.end(), offset.begin());
    tets.resize(offset.back());
    std::vector<Index> at(offset.begin(), offset.end() - 1);
    for (Index c = 0; c < cells.rows(); ++c)
      for (int k = 0; k < 4; ++k) tets[at[cells(c, k)]++] = c;
  }
};

// Every triangle of every tet, corners sorted, once per tet it bounds
// (sorted: an interior triangle appears twice in a row, a boundary one once).
std::vector<std::array<Index, 3>> tet_faces(const SimplexMatrix& cells) {
  std::vector<std::array<Index, 3>> faces;
  faces.reserve(4 * static_cast<size_t>(cells.rows()));
  for (Index c = 0; c < cells.rows(); ++c)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> f{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = cells(c, k);
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// Union-find over a handful of link vertices.
struct Components {
  std::vector<int> parent;
  explicit Components(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) { return parent[a] == a ? a : parent[a] = find(parent[a]); }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

class SimplePoints {
 public:
  SimplePoints(const SimplexMatrix& cells, Index vertices) : cells_(cells), stars_(cells, vertices) {
    boundary_.assign(vertices, false);
    // Vertices on the triangulation's boundary (the box) have a disk for a
    // link; the zero set never comes near them (the field is positive
    // there), so they never change sign here.
    const std::vector<std::array<Index, 3>> faces = tet_faces(cells);
    for (size_t i = 0; i < faces.size();) {
      size_t j = i + 1;
      while (j < faces.size() && faces[j] == faces[i]) ++j;
      if (j - i == 1)
        for (const Index v : faces[i]) boundary_[v] = true;
      i = j;
    }
  }

  bool on_boundary(Index v) const { return boundary_[v]; }

  // The negative and the positive part of v's link (a triangulated sphere):
  // each's vertex count, Euler characteristic and number of components.
  struct LinkParts {
    std::array<int, 2> vertices{0, 0}, chi{0, 0}, components{0, 0};
  };

  LinkParts link_parts(Index v, const std::vector<signed char>& negative) const {
    std::vector<Index> ids;
    for (Index i = stars_.offset[v]; i < stars_.offset[v + 1]; ++i)
      for (int k = 0; k < 4; ++k)
        if (cells_(stars_.tets[i], k) != v) ids.push_back(cells_(stars_.tets[i], k));
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    auto local = [&](Index w) { return static_cast<int>(std::lower_bound(ids.begin(), ids.end(), w) - ids.begin()); };
    const auto sign = [&](int a) { return negative[ids[a]] ? 0 : 1; };
    const int n = static_cast<int>(ids.size());
    LinkParts parts;
    std::array<int, 2> edges{0, 0}, triangles{0, 0};
    for (int a = 0; a < n; ++a) ++parts.vertices[sign(a)];
    Components components(n);
    std::vector<std::pair<int, int>> seen;
    std::array<int, 2> edge_sides{0, 0};  // a link edge's sides: one per link triangle it bounds
    const Index link_triangles = stars_.offset[v + 1] - stars_.offset[v];
    for (Index i = stars_.offset[v]; i < stars_.offset[v + 1]; ++i) {
      std::array<int, 3> t{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (cells_(stars_.tets[i], k) != v) t[j++] = local(cells_(stars_.tets[i], k));
      if (sign(t[0]) == sign(t[1]) && sign(t[1]) == sign(t[2])) ++triangles[sign(t[0])];
      for (int a = 0; a < 3; ++a) {
        const int p = std::min(t[a], t[(a + 1) % 3]), q = std::max(t[a], t[(a + 1) % 3]);
        if (sign(p) != sign(q)) continue;
        ++edge_sides[sign(p)];
        seen.emplace_back(p, q);
        components.join(p, q);
      }
    }
    // The link of an interior point is a triangulated sphere (T = 2V - 4):
    // each of its edges bounds two of its triangles, so the edges are half
    // their sides. Any other link has its edges told apart one by one.
    if (link_triangles == 2 * static_cast<Index>(n) - 4) {
      for (int s = 0; s < 2; ++s) edges[s] = edge_sides[s] / 2;
    } else {
      std::sort(seen.begin(), seen.end());
      seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
      for (const auto& [p, q] : seen) ++edges[sign(p)];
    }
    for (int s = 0; s < 2; ++s) parts.chi[s] = parts.vertices[s] - edges[s] + triangles[s];
    for (int a = 0; a < n; ++a)
      if (components.find(a) == a) ++parts.components[sign(a)];
    return parts;
  }

  // Whether changing v's sign keeps the topology of the negative region and
  // of the positive one: its link splits into a negative part and a
  // positive part that are both non-empty, connected and of Euler
  // characteristic 1 (disks).
  static bool simple(const LinkParts& parts) {
    for (int s = 0; s < 2; ++s)
      if (parts.vertices[s] == 0 || parts.components[s] != 1 || parts.chi[s] != 1) return false;
    return true;
  }
  bool simple(Index v, const std::vector<signed char>& negative) const { return simple(link_parts(v, negative)); }

 private:
  const SimplexMatrix& cells_;
  Stars stars_;
  std::vector<bool> boundary_;
};


// Betti numbers of the negative region of a tetrahedralization (the full
// subcomplex on the negative points, which the zero set bounds): pieces,
// handles, cavities (pieces of the positive region that do not reach the
// triangulation's boundary).
class BettiNumbers {
 public:
  BettiNumbers(const SimplexMatrix& cells, Index vertices, const SimplePoints& points)
      : n_(vertices), points_(points), tets_(cells) {
    std::vector<std::array<Index, 3>> faces = tet_faces(cells);
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    edges_ = tet_edges(cells), faces_ = std::move(faces);
  }

  // Euler characteristic of the negative region.
  Index chi(const std::vector<signed char>& negative) const {
    Index chi = 0;
    for (Index v = 0; v < n_; ++v) chi += negative[v];
    for (const auto& e : edges_) chi -= negative[e[0]] && negative[e[1]];
    for (const auto& f : faces_) chi += negative[f[0]] && negative[f[1]] && negative[f[2]];
    for (Index c = 0; c < tets_.rows(); ++c)
      chi -= negative[tets_(c, 0)] && negative[tets_(c, 1)] && negative[tets_(c, 2)] && negative[tets_(c, 3)];
    return chi;
  }

  std::array<Index, 3> operator()(const std::vector<signed char>& negative) const {
    return with_chi(negative, chi(negative));
  }

  // The Betti numbers, given the region's Euler characteristic.
  std::array<Index, 3> with_chi(const std::vector<signed char>& negative, Index chi) const {
    Components parts(static_cast<int>(n_));
    for (const auto& e : edges_)
      if (negative[e[0]] == negative[e[1]]) parts.join(e[0], e[1]);
    std::vector<signed char> root_kind(n_, 0);  // 1: a negative piece, 2: a positive one, 3: positive, touching the boundary
    for (Index v = 0; v < n_; ++v) {
      signed char& kind = root_kind[parts.find(static_cast<int>(v))];
      if (negative[v]) kind = 1;
      else if (points_.on_boundary(v)) kind = 3;
      else if (kind == 0) kind = 2;
    }
    Index pieces = 0, cavities = 0;
    for (const signed char kind : root_kind) pieces += kind == 1, cavities += kind == 2;
    return {pieces, pieces + cavities - chi, cavities};
  }

 private:
  Index n_;
  const SimplePoints& points_;
  const SimplexMatrix& tets_;
  std::vector<std::array<Index, 2>> edges_;
  std::vector<std::array<Index, 3>> faces_;
};


}  // namespace

std::array<Index, 3> betti_numbers(const SimplexMatrix& cells, const Eigen::VectorXd& field) {
  const Index n = static_cast<Index>(field.size());
  const SimplePoints points(cells, n);
  std::vector<signed char> negative(n);
  for (Index v = 0; v < n; ++v) negative[v] = field(v) < 0;
  return BettiNumbers(cells, n, points)(negative);
}

namespace {

// The points of the pieces of the region where `field` is negative (joined
// by edges of `cells`) that hold at least kLastingPiece of the largest
// piece's points, and how many such pieces there are. Smaller pieces are
// left to vanish as the blend has them.
constexpr double kLastingPiece = 0.25;
std::pair<std::vector<char>, Index> lasting_pieces(const SimplexMatrix& cells, const Eigen::VectorXd& field) {
  const Index n = static_cast<Index>(field.size());
  Components parts(static_cast<int>(n));
  for (Index c = 0; c < cells.rows(); ++c)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (field(cells(c, i)) < 0 && field(cells(c, j)) < 0)
          parts.join(static_cast<int>(cells(c, i)), static_cast<int>(cells(c, j)));
  std::vector<Index> size(n, 0);
  for (Index v = 0; v < n; ++v)
    if (field(v) < 0) ++size[parts.find(static_cast<int>(v))];
  const Index largest = n ? *std::max_element(size.begin(), size.end()) : 0;
  std::vector<char> lasting(n, 0);
  Index count = 0;
  for (Index v = 0; v < n; ++v) {
    const Index root = parts.find(static_cast<int>(v));
    lasting[v] = field(v) < 0 && static_cast<double>(size[root]) >= kLastingPiece * static_cast<double>(largest);
    count += lasting[v] && root == v;
  }
  return {std::move(lasting), count};
}

}  // namespace

std::vector<std::array<Index, 2>> tet_edges(const SimplexMatrix& cells) {
  std::vector<std::array<Index, 2>> edges;
  edges.reserve(6 * static_cast<size_t>(cells.rows()));
  for (Index c = 0; c < cells.rows(); ++c)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        edges.push_back({std::min(cells(c, a), cells(c, b)), std::max(cells(c, a), cells(c, b))});
  std::sort(edges.begin(), edges.end()), edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

Bridge bridge_between_pieces(const SimplexMatrix& cells, const PointMatrix& points, const Eigen::VectorXd& field,
                             Index pieces) {
  const Index n = static_cast<Index>(field.size());
  struct Edge {
    double height;  // the larger value of its two ends: a path's height is its highest edge's
    Index a, b;
  };
  Bridge bridge;
  const auto [anchor, lasting] = lasting_pieces(cells, field);
  if (lasting <= pieces) return bridge;
  std::vector<Edge> edges;
  for (const auto& [a, b] : tet_edges(cells)) edges.push_back({std::max(field(a), field(b)), a, b});
  std::sort(edges.begin(), edges.end(),
            [](const Edge& x, const Edge& y) { return std::tie(x.height, x.a, x.b) < std::tie(y.height, y.a, y.b); });
  // Kruskal's minimum spanning forest by height, up to the edge that leaves
  // `pieces` trees holding a lasting piece's point: its paths between them
  // are the lowest (least highest value) there are.
  Components trees(static_cast<int>(n));
  std::vector<char> holds_lasting(anchor);
  Index lasting_trees = 0;
  for (Index v = 0; v < n; ++v) lasting_trees += anchor[v];
  std::vector<std::vector<Index>> forest(n);
  for (size_t e = 0; e < edges.size() && lasting_trees > pieces; ++e) {
    const int ra = trees.find(static_cast<int>(edges[e].a)), rb = trees.find(static_cast<int>(edges[e].b));
    if (ra == rb) continue;
    if (holds_lasting[ra] && holds_lasting[rb]) --lasting_trees;
    trees.parent[ra] = rb;
    holds_lasting[rb] = holds_lasting[rb] || holds_lasting[ra];
    forest[edges[e].a].push_back(edges[e].b), forest[edges[e].b].push_back(edges[e].a);
  }
  // The forest's leaves off the lasting pieces, pruned until every leaf is
  // on one: what stays of them lies on a path between two lasting pieces.
  std::vector<Index> degree(n), leaves;
  for (Index v = 0; v < n; ++v) {
    degree[v] = static_cast<Index>(forest[v].size());
    if (!anchor[v] && degree[v] <= 1) leaves.push_back(v);
  }
  std::vector<char> pruned(n, 0);
  while (!leaves.empty()) {
    const Index v = leaves.back();
    leaves.pop_back();
    if (pruned[v]) continue;
    pruned[v] = 1;
    for (const Index w : forest[v])
      if (!pruned[w] && --degree[w] <= 1 && !anchor[w]) leaves.push_back(w);
  }
  // The forest's edges between points that stay, one of them off the
  // lasting pieces: the lowest paths' steps across the gaps between them.
  for (Index v = 0; v < n; ++v) {
    if (pruned[v] || anchor[v]) continue;
    bridge.height = std::max(bridge.height, field(v));
    for (const Index w : forest[v])
      if (!pruned[w] && (anchor[w] || w > v)) {
        bridge.segments.push_back({points.row(v), points.row(w)});
        bridge.into_piece.push_back(anchor[w]);
      }
  }
  return bridge;
}

namespace {

// Of the points `held` on the layer before, those in the negative region
// that the blend (`value`) wants out of it and whose removal has become
// simple (with `negative` the signs there): a thread held to a part that
// has since vanished becomes simple point by point from its free end, and
// changes judged one by one in the order they happen take only those that
// come after their outer neighbour, one or two a layer where the blend
// rises towards the thread's root. Found in rounds (each the points simple
// at its start, removed one by one, judged again), in the thread's order
// from its end inwards; returns the first 1 / `layers_left` of them (all on
// the fill's layer), so that the thread is gone by the fill: it does not
// vanish in the fill's slab, which is a fraction of a layer thick.
std::vector<Index> release_held(const SimplePoints& points, const std::vector<Index>& held,
                                const Eigen::VectorXd& value, const std::vector<signed char>& negative,
                                size_t layers_left) {
  std::vector<signed char> trial = negative;
  std::vector<Index> order, waiting;
  for (const Index v : held)
    if (negative[v] && value(v) >= 0) waiting.push_back(v);
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<Index> round, still;
    for (const Index v : waiting) (points.simple(v, trial) ? round : still).push_back(v);
    for (const Index v : round) {
      if (!points.simple(v, trial)) {
        still.push_back(v);
        continue;
      }
      trial[v] = 0;
      order.push_back(v);
      changed = true;
    }
    waiting = std::move(still);
  }
  order.resize((order.size() + layers_left - 1) / std::max<size_t>(layers_left, 1));
  return order;
}

}  // namespace

Index preserve_topology(const SimplexMatrix& cells, std::vector<Eigen::VectorXd>& field, int first, double floor,
                        const std::array<Index, 3>& floor_betti, const std::array<Index, 3>& ceiling_betti,
                        const std::vector<std::vector<bool>>& bridges) {
  if (field.empty()) return 0;
  const Index n = static_cast<Index>(field.front().size());
  const SimplePoints points(cells, n);
  const BettiNumbers betti(cells, n, points);
  std::vector<signed char> negative(n);
  for (Index v = 0; v < n; ++v) negative[v] = field[first - 1](v) < 0;
  Index chi = betti.chi(negative);
  std::array<Index, 3> now = betti.with_chi(negative, chi);
  Index held = 0;
  std::vector<Index> refused;  // the points held on the layer before
  for (size_t layer = static_cast<size_t>(first); layer < field.size(); ++layer) {
    Eigen::VectorXd& value = field[layer];
    const Eigen::VectorXd& before = field[layer - 1];
    // Held points free to leave go first: their values on the layer before
    // are near zero, so between the layers their changes come first.
    for (const Index v : release_held(points, refused, value, negative, field.size() - layer)) negative[v] = 0;
    refused.clear();
    // The sign changes the blend asks for, in the order they happen between
    // the layers (each point's field is linear in time there), each judged
    // after those before it, so the zero set between the layers passes
    // through them in that order.
    std::vector<std::pair<double, Index>> wanted;
    for (Index v = 0; v < n; ++v)
      if ((value(v) < 0) != static_cast<bool>(negative[v]) && !points.on_boundary(v))
        wanted.emplace_back(before(v) / (before(v) - value(v)), v);
    std::sort(wanted.begin(), wanted.end());
    int counted = 0;
    // A change of topology at v: made (and v's sign changed) where every
    // Betti number it changes goes down, towards the floor, or, for a
    // bridge's point joining the negative region, stays within the ends'.
    // Adding v to the negative region changes its Euler characteristic by
    // 1 - chi(link's negative part); removing it, by the opposite.
    const auto topology_change_allowed = [&](Index v, const SimplePoints::LinkParts& parts) {
      const Index step = negative[v] ? parts.chi[0] - 1 : 1 - parts.chi[0];
      const bool bridging = !bridges[layer].empty() && bridges[layer][v] && !negative[v];
      negative[v] = !negative[v];
      const std::array<Index, 3> next = betti.with_chi(negative, chi + step);
      bool allowed = true;
      for (int i = 0; i < 3; ++i)
        allowed = allowed && (next[i] == now[i] || (next[i] < now[i] ? next[i] >= floor_betti[i]
                                                                    : bridging && next[i] <= ceiling_betti[i]));
      if (allowed) now = next, chi += step;
      else negative[v] = !negative[v];
      return allowed;
    };
    for (const auto& [when, v] : wanted) {
      const SimplePoints::LinkParts parts = points.link_parts(v, negative);
      if (SimplePoints::simple(parts)) {
        negative[v] = !negative[v];
        continue;
      }
      if (!(counted++ < kTopologyTries && topology_change_allowed(v, parts))) refused.push_back(v);
    }
    // A held value is jittered like the blend's, salted by its sign: the
    // two halves can hold the same point with opposite signs on their fill
    // layers, and exactly opposite values there would cut the fill's edges
    // at its middle time (0.5), where the zero set would then hold edges
    // lying in the frame's plane: a frame pinched along them. A point held
    // out of the negative region keeps kHeldOutside floors from zero: the
    // staircase of the slab after it widens the solid (add_stack), and a
    // gap a floor wide would close there, joining what it keeps apart.
    for (const Index v : refused)
      value(v) = jittered(negative[v] ? -floor : kHeldOutside * floor, v, static_cast<int>(layer),
                          negative[v] ? 0x401d : 0x401e);
    held += static_cast<Index>(refused.size());
  }
  return held;
}

namespace {

double depth_inside(const EndDistances& distances, Index v) {
  return std::max(0.0, -std::min(distances.s(v), distances.t(v)));
}

}  // namespace

Index keep_gaps_open(const PointMatrix& points, const std::vector<std::array<Index, 2>>& edges,
                     const EndDistances& distances, const OutsideBoth& outside_both,
                     const std::vector<bool>& negative, Eigen::VectorXd& bump) {
  const auto lowered = [&](Index v) { return bump(v) > 0 || negative[v]; };
  std::vector<std::array<Index, 2>> uncovered;
  std::vector<Eigen::Vector3d> samples;
  for (const auto& [a, b] : edges) {
    if (!(bump(a) > 0 || bump(b) > 0) || !lowered(a) || !lowered(b)) continue;
    const Eigen::Vector3d p = points.row(a), q = points.row(b);
    const double length = (q - p).norm(), from = depth_inside(distances, a), to = length - depth_inside(distances, b);
    if (from >= to) continue;
    uncovered.push_back({a, b});
    for (int k = 0; k < kGapSamples; ++k)
      samples.push_back(p + (q - p) * ((from + (to - from) * (k + 0.5) / kGapSamples) / length));
  }
  PointMatrix at(static_cast<Index>(samples.size()), 3);
  for (size_t i = 0; i < samples.size(); ++i) at.row(static_cast<Index>(i)) = samples[i];
  const Eigen::Array<bool, Eigen::Dynamic, 1> outside = samples.empty() ? Eigen::Array<bool, Eigen::Dynamic, 1>()
                                                                        : outside_both(at);
  Index taken = 0;
  for (size_t e = 0; e < uncovered.size(); ++e) {
    const auto [a, b] = uncovered[e];
    if (!(bump(a) > 0 || bump(b) > 0) || !lowered(a) || !lowered(b) ||
        !outside.segment(static_cast<Index>(e) * kGapSamples, kGapSamples).any())
      continue;
    bump(a) = bump(b) = 0;
    ++taken;
  }
  return taken;
}

void keep_bump_inside(const PointMatrix& points, const std::vector<std::array<Index, 2>>& edges,
                      const EndDistances& distances, const Eigen::VectorXd& bump, std::vector<Eigen::VectorXd>& field,
                      size_t layer, const Eigen::VectorXd& unbumped, double floor) {
  const auto inside = [&](Index v) { return depth_inside(distances, v); };
  // q's least positive value on the layer and its neighbours (0: none).
  const auto least_positive = [&](Index q) {
    double least = 0;
    for (size_t k = layer > 0 ? layer - 1 : 0; k <= std::min(layer + 1, field.size() - 1); ++k)
      if (field[k](q) > 0 && (least == 0 || field[k](q) < least)) least = field[k](q);
    return least;
  };
  Eigen::VectorXd lowest = Eigen::VectorXd::Constant(bump.size(), -std::numeric_limits<double>::infinity());
  for (const auto& edge : edges)
    for (const auto& [p, q] : {std::pair{edge[0], edge[1]}, std::pair{edge[1], edge[0]}}) {
      if (bump(p) <= 0) continue;
      const double length = (points.row(p) - points.row(q)).norm(), v = least_positive(q);
      if (inside(p) + inside(q) >= length || v == 0) continue;
      lowest(p) = std::max(lowest(p), -inside(p) * v / (length - inside(p)));
    }
  Eigen::VectorXd& value = field[layer];
  for (Index p = 0; p < bump.size(); ++p)
    if (bump(p) > 0) {
      const double lifted = jittered(std::min(lowest(p), -floor), p, static_cast<int>(layer), 0x401f);
      value(p) = std::min(unbumped(p), std::max(value(p), lifted));
    }
}

}  // namespace animanifold::morph_field
