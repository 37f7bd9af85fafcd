// The layers of the skeleton method's push (see morph_layers.hpp).
#include "morph_layers.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/exact_orientation.hpp"
#include "animanifold/surface_distance.hpp"
#include "simplex_key.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace animanifold {

namespace {

// Where in the layer the prisms over the split cells end and those over the
// fill's cells begin (a share of the layer's thickness from the end), and
// how high the free vertices go at most (a share of that: every prism keeps
// a top above its bottom).
constexpr double kSplitLevel = 0.9;
constexpr double kHighest = 0.98;
// Edges outside the input longer than this share of the plane's size are
// split (rounds of them: the halves can still be too long).
constexpr double kLongestOutsideEdge = 1.0 / 25;
constexpr int kRefinementRounds = 6;
// ... and at most this many times as many points as the plane has are added
// (the halves of a long edge across a wide gap are split again and again).
constexpr Index kRefinementBudget = 1;
// Relative volume (|det| over the longest edge cubed) below which a cell is
// flat to rounding (peel_boundary_slivers).
constexpr double kSliver = 1e-12;
// A long edge is not split where a cell would come out thinner than this
// (relative volume): cells flat to rounding on a flat side of the hull, whose
// frames the slices' rounding folds.
constexpr double kThinnestRefinedCell = 1e-6;
// Free vertices at least this share of the farthest one's distance from the
// input go all the way into the layer; nearer ones in proportion, but at
// least kLowestLevel of the way (free_vertex_levels).
constexpr double kOpenDistance = 0.25;
constexpr double kLowestLevel = 0.05;
// Rounds of levelling the free vertices' heights (free_vertex_levels).
constexpr int kLevellingRounds = 20;

using FaceKey = SimplexKey<3>;  // a cell's facet (n <= 3 ids)
using FaceHash = SimplexKeyHash;

// The cells' vertex graph, and the free vertices on the boundary of their
// union (on a facet of one cell only): where a free vertex's path may end.
struct CellGraph {
  std::vector<std::vector<Index>> neighbours;
  std::vector<bool> sink;

  CellGraph(const SimplexMatrix& cells, Index count, const std::vector<bool>& free)
      : neighbours(count), sink(count, false) {
    const int corners = static_cast<int>(cells.cols());
    std::unordered_map<FaceKey, int, FaceHash> facets;
    for (Index c = 0; c < cells.rows(); ++c) {
      for (int drop = 0; drop < corners; ++drop) {
        FaceKey key{-1, -1, -1};
        for (int i = 0, j = 0; i < corners; ++i)
          if (i != drop) key[j++] = cells(c, i);
        std::sort(key.begin(), key.begin() + corners - 1);
        ++facets[key];
      }
      for (int a = 0; a < corners; ++a)  // an edge is listed once per cell it is in: harmless
        for (int b = a + 1; b < corners; ++b) {
          const Index u = cells(c, a), v = cells(c, b);
          neighbours[u].push_back(v), neighbours[v].push_back(u);
        }
    }
    for (const auto& [key, times] : facets)
      if (times == 1)
        for (int i = 0; i < corners - 1; ++i)
          if (free[key[i]]) sink[key[i]] = true;
  }
};

// Regions of free vertices (joined by edges between free vertices): each
// vertex's region (-1 for none) and whether each region reaches a sink.
struct FreeRegions {
  std::vector<Index> region;
  std::vector<bool> reaches_sink;

  FreeRegions(const CellGraph& graph, const std::vector<bool>& free) : region(graph.neighbours.size(), -1) {
    const Index count = static_cast<Index>(graph.neighbours.size());
    for (Index v = 0; v < count; ++v) {
      if (!free[v] || region[v] >= 0 || graph.neighbours[v].empty()) continue;
      const Index id = static_cast<Index>(reaches_sink.size());
      reaches_sink.push_back(false);
      std::vector<Index> stack{v};
      region[v] = id;
      while (!stack.empty()) {
        const Index u = stack.back();
        stack.pop_back();
        if (graph.sink[u]) reaches_sink[id] = true;
        for (const Index w : graph.neighbours[u])
          if (free[w] && region[w] < 0) region[w] = id, stack.push_back(w);
      }
    }
  }

  bool levelled(Index v) const { return region[v] >= 0 && reaches_sink[region[v]]; }
};

// Down: every levelled vertex no higher than its best path to a sink, by
// the path's lowest level (highest first). Whether a level changed.
bool level_down(const CellGraph& graph, const FreeRegions& regions, Eigen::VectorXd& level) {
  const Index count = static_cast<Index>(level.size());
  std::vector<double> best(count, -1.0);
  std::priority_queue<std::pair<double, Index>> widest;
  for (Index v = 0; v < count; ++v)
    if (graph.sink[v] && regions.levelled(v)) best[v] = level(v), widest.emplace(level(v), v);
  while (!widest.empty()) {
    const auto [at, v] = widest.top();
    widest.pop();
    if (at < best[v]) continue;
    for (const Index w : graph.neighbours[v]) {
      if (!regions.levelled(w)) continue;
      const double through = std::min(level(w), at);
      if (through > best[w]) best[w] = through, widest.emplace(through, w);
    }
  }
  bool changed = false;
  for (Index v = 0; v < count; ++v)
    if (regions.levelled(v) && best[v] < level(v)) level(v) = std::max(best[v], 0.0), changed = true;
  return changed;
}

// Up: every levelled vertex no lower than its best path to the input (a
// vertex that is not free), by the path's highest level (lowest first).
// Whether a level changed.
bool level_up(const CellGraph& graph, const FreeRegions& regions, const std::vector<bool>& free,
              Eigen::VectorXd& level) {
  const Index count = static_cast<Index>(level.size());
  std::vector<double> lowest(count, std::numeric_limits<double>::infinity());
  std::priority_queue<std::pair<double, Index>, std::vector<std::pair<double, Index>>, std::greater<>> narrowest;
  for (Index v = 0; v < count; ++v)
    if (!free[v] && !graph.neighbours[v].empty()) lowest[v] = 0.0, narrowest.emplace(0.0, v);
  while (!narrowest.empty()) {
    const auto [at, v] = narrowest.top();
    narrowest.pop();
    if (at > lowest[v]) continue;
    for (const Index w : graph.neighbours[v]) {
      if (!free[w]) continue;
      const double through = std::max(level(w), at);
      if (through < lowest[w]) lowest[w] = through, narrowest.emplace(through, w);
    }
  }
  bool changed = false;
  for (Index v = 0; v < count; ++v)
    if (regions.levelled(v) && lowest[v] > level(v) && std::isfinite(lowest[v])) level(v) = lowest[v], changed = true;
  return changed;
}

// Per vertex of the cells (#C by n+1 over `spatial`'s rows): a level in
// [0, 1] — 0 where not `free`, `distance_level` where free (its distance
// from the input, as a share of a reference: the distance field's level sets
// are offsets of the input, so a hole opens along its axis first and a thin
// film between the input and its hull empties last) — then levelled: a
// vertex above every path from it to the boundary (facets of one cell: the
// convex hull, where the frame meets the outside) comes down to the best
// such path's lowest level, else the frames would hold its region as a
// bubble (the distance field's peaks on the medial axis that the cells do
// not join to the hull at their height); one below every path to the input
// comes up to the best one's highest (else an island) — rounds of both until
// neither changes anything. Free regions without a boundary vertex (a cavity
// of the input, a bubble by nature) keep their levels (`sealed` counts their
// vertices); `levelled` counts the vertices the levelling moved.
Eigen::VectorXd free_vertex_levels(const PointMatrix& spatial, const SimplexMatrix& cells, const std::vector<bool>& free,
                                   const Eigen::VectorXd& distance_level, Index& sealed, Index& levelled) {
  const Index count = static_cast<Index>(spatial.rows());
  const CellGraph graph(cells, count, free);
  const FreeRegions regions(graph, free);
  Eigen::VectorXd level = Eigen::VectorXd::Zero(count);
  sealed = 0;
  for (Index v = 0; v < count; ++v) {
    if (regions.region[v] < 0) continue;
    level(v) = distance_level(v);
    sealed += !regions.reaches_sink[regions.region[v]];
  }
  // The levelling, over the vertices of regions that reach the boundary.
  const Eigen::VectorXd unlevelled = level;
  for (int round = 0; round < kLevellingRounds; ++round) {
    const bool down = level_down(graph, regions, level);
    const bool up = level_up(graph, regions, free, level);
    if (!down && !up) break;
  }
  levelled = 0;
  for (Index v = 0; v < count; ++v) levelled += std::abs(level(v) - unlevelled(v)) > 1e-12;
  return level;
}

// Edges of outside cells that are no edge of another cell (inside or flat
// on the surface) and longer than `longest`, longest first.
std::vector<std::vector<Index>> long_outside_edges(const PointMatrix& spatial, const SimplexMatrix& cells,
                                                   const std::vector<bool>& outside, double longest) {
  const int corners = static_cast<int>(cells.cols());
  // Edges as (smaller id, larger id) in one 64-bit key.
  auto key = [](Index a, Index b) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32 |
           static_cast<std::uint32_t>(std::max(a, b));
  };
  std::vector<std::uint64_t> covered, candidates;
  for (Index c = 0; c < cells.rows(); ++c)
    for (int a = 0; a < corners; ++a)
      for (int b = a + 1; b < corners; ++b) (outside[c] ? candidates : covered).push_back(key(cells(c, a), cells(c, b)));
  for (std::vector<std::uint64_t>* keys : {&covered, &candidates}) {
    std::sort(keys->begin(), keys->end());
    keys->erase(std::unique(keys->begin(), keys->end()), keys->end());
  }
  std::vector<std::pair<double, std::uint64_t>> edges;
  for (const std::uint64_t e : candidates) {
    if (std::binary_search(covered.begin(), covered.end(), e)) continue;
    const Index a = static_cast<Index>(e >> 32), b = static_cast<Index>(e & 0xffffffffu);
    const double length = (spatial.row(a) - spatial.row(b)).norm();
    if (length > longest) edges.emplace_back(-length, e);  // longest first, then by ids
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<Index>> out;
  out.reserve(edges.size());
  for (const auto& [length, e] : edges) out.push_back({static_cast<Index>(e >> 32), static_cast<Index>(e & 0xffffffffu)});
  return out;
}

// Cells flagged `candidate` (outside the input and flat to rounding) that
// lie on the triangulation's boundary are peeled off it, one at a time, as
// long as what remains stays a ball (a shelling step: the face spanned by
// the corners opposite the removed cell's boundary facets must not lie on
// the boundary). Such cells lie under a nearly planar part of the convex
// hull (four of its points coplanar to rounding: a pair of parallel rings of
// two icospheres), between the hull's two triangles and the other diagonal
// inside: the heights, linear on each, differ across them, and the frames
// fold there within the plane. Returns which cells are kept.
std::vector<bool> peel_boundary_slivers(const SimplexMatrix& cells, const std::vector<bool>& candidate) {
  const int corners = static_cast<int>(cells.cols());
  std::vector<bool> kept(cells.rows(), true);
  auto facet_of = [&](Index c, int drop) {
    FaceKey key{-1, -1, -1};
    for (int i = 0, j = 0; i < corners; ++i)
      if (i != drop) key[j++] = cells(c, i);
    std::sort(key.begin(), key.begin() + corners - 1);
    return key;
  };
  std::unordered_map<FaceKey, int, FaceHash> count;
  for (Index c = 0; c < cells.rows(); ++c)
    for (int drop = 0; drop < corners; ++drop) ++count[facet_of(c, drop)];
  // The boundary's faces of every size (keys padded with -1). A peel only
  // adds to it (the removed cell's other facets come out); the facets it
  // takes away leave their faces listed, which only ever forbids a peel.
  std::unordered_map<FaceKey, int, FaceHash> on_boundary;
  auto add_boundary_facet = [&](const FaceKey& key) {
    for (unsigned mask = 1; mask < (1u << (corners - 1)); ++mask) {
      FaceKey sub{-1, -1, -1};
      for (int i = 0, j = 0; i < corners - 1; ++i)
        if (mask & (1u << i)) sub[j++] = key[i];
      on_boundary[sub] = 1;
    }
  };
  for (const auto& [key, times] : count)
    if (times == 1) add_boundary_facet(key);
  for (bool peeled = true; peeled;) {  // again while a peel exposes another candidate
    peeled = false;
    for (Index c = 0; c < cells.rows(); ++c) {
      if (!kept[c] || !candidate[c]) continue;
      FaceKey opposite{-1, -1, -1};
      int boundary = 0;
      for (int drop = 0; drop < corners; ++drop)
        if (count[facet_of(c, drop)] == 1) opposite[boundary++] = cells(c, drop);
      if (boundary == 0 || boundary == corners) continue;
      std::sort(opposite.begin(), opposite.begin() + boundary);
      if (on_boundary.count(opposite)) continue;
      kept[c] = false, peeled = true;
      for (int drop = 0; drop < corners; ++drop) {
        const FaceKey key = facet_of(c, drop);
        if (--count[key] == 1) add_boundary_facet(key);
      }
    }
  }
  return kept;
}

}  // namespace

void append_prism(const Index* cell, int corners, const Index* lower, const Index* upper, std::vector<Index>& out) {
  const int n = corners - 1;
  std::array<int, 4> order{0, 1, 2, 3};
  std::sort(order.begin(), order.begin() + corners, [&](int a, int b) { return cell[a] < cell[b]; });
  for (int r = 0; r <= n; ++r) {
    // Lower copies of the first n-r+1 in the order, upper copies of the last r+1.
    std::array<Index, 5> ids{};
    Eigen::MatrixXd reference = Eigen::MatrixXd::Zero(n + 2, n + 1);  // rows: corners; (cell's unit simplex, time)
    int c = 0;
    auto add = [&](int i, bool up) {
      const int slot = order[i];
      ids[c] = up ? upper[slot] : lower[slot];
      if (slot > 0) reference(c, slot - 1) = 1.0;
      reference(c, n) = up ? 1.0 : 0.0;
      ++c;
    };
    for (int i = 0; i <= n - r; ++i) add(i, false);
    for (int i = n - r; i <= n; ++i) add(i, true);
    Eigen::MatrixXd edges(n + 1, n + 1);
    for (int i = 0; i <= n; ++i) edges.row(i) = reference.row(i + 1) - reference.row(0);
    if (edges.determinant() < 0) std::swap(ids[0], ids[1]);
    out.insert(out.end(), ids.begin(), ids.begin() + n + 2);
  }
}

namespace {

// K's cells, positive on the coordinates the fill was decided on (where
// they are a proper triangulation of the plane), without the cells outside
// the input and flat to rounding on K's boundary (peel_boundary_slivers):
// the fill's cell under each shows at the layer's top as a face of no volume.
PlaneCells layer_cells(const PointMatrix& P, const PointMatrix& fill_points, const PlaneCells& plane, int n,
                       PlaneLayer& layer) {
  const int corners = n + 1;
  SimplexMatrix all_cells = plane.cells;
  const PointMatrix fill_spatial = fill_points.leftCols(n);
  for (Index c = 0; c < all_cells.rows(); ++c)
    if (exact_orientation(fill_spatial, all_cells.row(c).data()) < 0) std::swap(all_cells(c, 0), all_cells(c, 1));
  std::vector<bool> sliver(all_cells.rows(), false);
  {
    const PointMatrix exact_spatial = P.leftCols(n);
    for (Index c = 0; c < all_cells.rows(); ++c)
      sliver[c] = plane.outside[c] && relative_volume(exact_spatial, all_cells.row(c).data()) < kSliver;
  }
  const std::vector<bool> keep = peel_boundary_slivers(all_cells, sliver);
  PlaneCells kept;
  kept.cells.resize(std::count(keep.begin(), keep.end(), true), corners);
  for (Index c = 0, r = 0; c < all_cells.rows(); ++c)
    if (keep[c]) {
      kept.cells.row(r++) = all_cells.row(c);
      kept.outside.push_back(plane.outside[c]);
      kept.flat.push_back(plane.flat[c]);
    }
  kept.free = plane.free;
  layer.peeled_slivers = static_cast<Index>(all_cells.rows() - kept.cells.rows());
  return kept;
}

// K split at the layer's coordinates (the first n columns of P: exact): the
// faces outside the input without a free vertex, then the long edges
// outside it, since the heights are linear on each cell and a hole opens
// only as finely as the cells outside the input are.
struct SplitPlane {
  Index points;                           // K's points (the split points follow)
  PointMatrix spatial;                    // K's points and the split points
  SimplexMatrix split;                    // the split cells
  std::vector<bool> outside;              // per split cell
  std::vector<std::vector<Index>> faces;  // every face split, in order
  PointMatrix split_points;               // where each split went, in order

  SplitPlane(const PointMatrix& P, const PlaneCells& kept, int n, PlaneLayer& layer)
      : points(static_cast<Index>(P.rows())), spatial(P.leftCols(n)), split(kept.cells), outside(kept.outside),
        split_points(0, n) {
    split_these(uncovered_outside_faces(kept), false);
    layer.split_faces = static_cast<Index>(faces.size());
    refine_long_edges(kept.cells, layer.split_faces);
    layer.refinement_points = static_cast<Index>(faces.size()) - layer.split_faces;
  }

 private:
  void split_these(const std::vector<std::vector<Index>>& these, bool optional) {
    std::vector<Index> parents;
    SplitOptions how;
    how.skip_unsafe = optional;
    how.thinnest = optional ? kThinnestRefinedCell : 0.0;
    how.parents = &parents;
    const Index before = static_cast<Index>(spatial.rows());
    const IndexVector added = split_faces(spatial, split, these, how);
    std::vector<bool> inherited(parents.size());
    for (size_t r = 0; r < parents.size(); ++r) inherited[r] = outside[parents[r]];
    outside = std::move(inherited);
    for (Index f = 0; f < added.size(); ++f)
      if (added(f) >= 0) faces.push_back(these[static_cast<size_t>(f)]);
    split_points.conservativeResize(spatial.rows() - points, split_points.cols());
    split_points.bottomRows(spatial.rows() - before) = spatial.bottomRows(spatial.rows() - before);
  }

  void refine_long_edges(const SimplexMatrix& cells, Index split_faces_count) {
    std::vector<bool> in_cells(points, false);
    for (Index c = 0; c < cells.rows(); ++c)
      for (int i = 0; i < cells.cols(); ++i) in_cells[cells(c, i)] = true;
    const Index points_in_plane = static_cast<Index>(std::count(in_cells.begin(), in_cells.end(), true));
    const double longest = kLongestOutsideEdge * (spatial.topRows(points).colwise().maxCoeff() -
                                                  spatial.topRows(points).colwise().minCoeff()).norm();
    for (int round = 0; round < kRefinementRounds; ++round) {
      std::vector<std::vector<Index>> long_edges = long_outside_edges(spatial, split, outside, longest);
      const Index budget = kRefinementBudget * points_in_plane - (static_cast<Index>(faces.size()) - split_faces_count);
      if (static_cast<Index>(long_edges.size()) > budget) long_edges.resize(static_cast<size_t>(std::max<Index>(budget, 0)));
      if (long_edges.empty()) break;
      const size_t before = faces.size();
      split_these(long_edges, true);
      if (faces.size() == before) break;
    }
  }
};

// Which vertices of the split plane are free (K's free ones and every split
// point) and which its cells use, and how high each free vertex goes: all
// the way where it lies far from the input (a hole's axis), in proportion
// where it lies closer, never nothing (free_vertex_levels).
struct FreeHeights {
  std::vector<bool> free, used;
  Eigen::VectorXd level;

  FreeHeights(const SplitPlane& s, const PlaneCells& plane, const PointMatrix& input_points,
              const SimplexMatrix& input_faces, PlaneLayer& layer) {
    const Index local = static_cast<Index>(s.spatial.rows());
    free.assign(local, false), used.assign(local, false);
    for (Index v = 0; v < s.points && v < static_cast<Index>(plane.free.size()); ++v) free[v] = plane.free[v];
    for (Index v = s.points; v < local; ++v) free[v] = true;
    for (Index c = 0; c < s.split.rows(); ++c)
      for (int i = 0; i < s.split.cols(); ++i) used[s.split(c, i)] = true;
    std::vector<Index> free_ids;
    for (Index v = 0; v < local; ++v)
      if (free[v] && used[v]) free_ids.push_back(v);
    PointMatrix where(static_cast<Index>(free_ids.size()), s.spatial.cols());
    for (size_t i = 0; i < free_ids.size(); ++i) where.row(static_cast<Index>(i)) = s.spatial.row(free_ids[i]);
    const Eigen::VectorXd distance = distances_to_surface(where, input_points, input_faces);
    const double reference = kOpenDistance * (distance.size() ? distance.maxCoeff() : 0.0);
    Eigen::VectorXd distance_level = Eigen::VectorXd::Ones(local);
    for (size_t i = 0; i < free_ids.size(); ++i)
      if (reference > 0 && std::isfinite(distance(static_cast<Index>(i))))
        distance_level(free_ids[i]) = std::clamp(distance(static_cast<Index>(i)) / reference, kLowestLevel, 1.0);
    level = free_vertex_levels(s.spatial, s.split, free, distance_level, layer.sealed_vertices, layer.levelled_vertices);
  }
};

// Where the layer's copies of a vertex go: the end copies (at their
// heights) of the split plane's vertices, then the mid copies of K's
// vertices; the split points' mid copies are appended by the splits of the
// upper part.
struct LayerCopies {
  std::vector<Index> end_copy, mid_copy;
  double direction, mid_time;
};

// Appends the end and mid copies to P and records the free vertices' heights.
LayerCopies place_copies(PointMatrix& P, const SplitPlane& s, const FreeHeights& heights, double end_time,
                         double fill_time, PlaneLayer& layer) {
  const int n = static_cast<int>(s.spatial.cols());
  const Index local = static_cast<Index>(s.spatial.rows());
  LayerCopies copies{std::vector<Index>(local, -1), std::vector<Index>(local, -1), fill_time > end_time ? 1.0 : -1.0, 0};
  const double thickness = std::abs(fill_time - end_time);
  copies.mid_time = end_time + copies.direction * kSplitLevel * thickness;
  const double highest = kHighest * kSplitLevel * thickness;
  Index next = s.points;
  for (Index v = 0; v < local; ++v)
    if (heights.used[v]) copies.end_copy[v] = next++;
  for (Index v = 0; v < s.points; ++v)
    if (heights.used[v]) copies.mid_copy[v] = next++;
  P.conservativeResize(next, n + 1);
  double sum = 0;
  layer.smallest = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < local; ++v) {
    if (!heights.used[v]) continue;
    const double h = heights.free[v] ? highest * heights.level(v) : 0.0;
    const Index end = copies.end_copy[v], mid = copies.mid_copy[v];
    P.row(end).head(n) = s.spatial.row(v);
    P(end, n) = end_time + copies.direction * h;
    if (v < s.points) P.row(mid).head(n) = s.spatial.row(v), P(mid, n) = copies.mid_time;
    if (heights.free[v]) {
      layer.free_copies.push_back(end);
      ++layer.free_vertices;
      sum += h;
      layer.smallest = std::min(layer.smallest, h);
      layer.largest = std::max(layer.largest, h);
    } else {
      layer.end_copies.push_back(end);
    }
  }
  if (layer.free_vertices == 0) layer.smallest = 0;
  layer.mean = layer.free_vertices ? sum / layer.free_vertices : 0.0;
  return copies;
}

// Prisms over `cells` between the copies `from` (towards the end) and `to`
// (towards the fill), appended to `rows`.
void append_prisms(const SimplexMatrix& cells, const std::vector<Index>& from, const std::vector<Index>& to,
                   double direction, std::vector<Index>& rows) {
  std::array<Index, 4> lower{}, upper{};
  for (Index c = 0; c < cells.rows(); ++c) {
    for (int i = 0; i < cells.cols(); ++i) {
      const Index v = cells(c, i);
      lower[i] = direction > 0 ? from[v] : to[v];
      upper[i] = direction > 0 ? to[v] : from[v];
    }
    append_prism(cells.row(c).data(), static_cast<int>(cells.cols()), lower.data(), upper.data(), rows);
  }
}

// The upper part: prisms over K's cells between the mid copies and the
// fill's own points, split at their mid level like K was (the k-th split
// appends the k-th split point's mid copy).
SimplexMatrix upper_part(PointMatrix& P, const SimplexMatrix& cells, const SplitPlane& s, LayerCopies& copies) {
  const int n = static_cast<int>(s.spatial.cols()), D = n + 1;
  std::vector<Index> own(static_cast<size_t>(s.points));
  std::iota(own.begin(), own.end(), Index{0});
  std::vector<Index> rows;
  append_prisms(cells, copies.mid_copy, own, copies.direction, rows);
  SimplexMatrix part = Eigen::Map<SimplexMatrix>(rows.data(), static_cast<Index>(rows.size()) / (D + 1), D + 1);
  const Index local = static_cast<Index>(s.spatial.rows());
  for (Index v = s.points; v < local; ++v) copies.mid_copy[v] = static_cast<Index>(P.rows()) + (v - s.points);
  std::vector<std::vector<Index>> mid_faces(s.faces.size());
  PointMatrix positions(static_cast<Index>(s.faces.size()), D);
  for (size_t f = 0; f < s.faces.size(); ++f) {
    for (const Index v : s.faces[f]) mid_faces[f].push_back(copies.mid_copy[v]);
    positions.row(static_cast<Index>(f)).head(n) = s.split_points.row(static_cast<Index>(f));
    positions(static_cast<Index>(f), n) = copies.mid_time;
  }
  SplitOptions at_mid;
  at_mid.positions = &positions;
  const IndexVector split_mid = split_faces(P, part, mid_faces, at_mid);
  for (Index f = 0; f < split_mid.size(); ++f)
    if (split_mid(f) != copies.mid_copy[s.points + f]) fail<MeshingError>("the layer's splits lost their order");
  return part;
}

}  // namespace

PlaneLayer plane_layer(PointMatrix& P, const PointMatrix& fill_points, const PlaneCells& plane,
                       const PointMatrix& input_points, const SimplexMatrix& input_faces, double end_time,
                       double fill_time) {
  const int D = static_cast<int>(P.cols()), n = D - 1, corners = n + 1;
  if (plane.cells.cols() != corners) fail<InputError>("a plane of R^", D, " has cells of ", corners, " corners");
  PlaneLayer layer;
  const PlaneCells kept = layer_cells(P, fill_points, plane, n, layer);
  const SplitPlane s(P, kept, n, layer);
  const FreeHeights heights(s, plane, input_points, input_faces, layer);
  LayerCopies copies = place_copies(P, s, heights, end_time, fill_time, layer);
  const SimplexMatrix upper = upper_part(P, kept.cells, s, copies);
  // The lower part: prisms over the split cells between the end copies and the mid copies.
  std::vector<Index> rows;
  append_prisms(s.split, copies.end_copy, copies.mid_copy, copies.direction, rows);
  const Index lower_rows = static_cast<Index>(rows.size()) / (D + 1);
  layer.simplices.resize(upper.rows() + lower_rows, D + 1);
  layer.simplices.topRows(upper.rows()) = upper;
  layer.simplices.bottomRows(lower_rows) = Eigen::Map<SimplexMatrix>(rows.data(), lower_rows, D + 1);
  return layer;
}

}  // namespace animanifold
