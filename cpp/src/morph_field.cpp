#include "morph_field.hpp"

#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"
#include "morph_field_internal.hpp"
#include "two_thread_work.hpp"
#include "zero_set.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <array>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <tuple>

namespace animanifold {

using namespace morph_field;

namespace {

// Samples of the zero set the blend's schedule is measured on
// (morph_field_timing.cpp).
constexpr int kScheduleSamples = 24;
// Rounds of refining an end's points where the zero set needs it.
constexpr int kRefineRounds = 2;
// The halves' curved edges (split_curved_edges): split where the blend at
// their middle is this share of the lattice spacing off linear, in up to
// this many rounds, down to this share of the spacing. At 0.05 a share of
// the teeth on a cube's rims stayed (they reach a lattice spacing down the
// sides); at 0.02 they are gone, for a few thousand points per half.
constexpr double kCurveTolerance = 0.02;
constexpr int kCurveRounds = 5;
constexpr double kCurveShortest = 0.1;
// Rounds of breaking an end's flat cells (points_off_flat_cells), each at
// this share of the first one's distance from the cell's plane.
constexpr double kFlatCellReach[] = {1.0, 2.0, 0.5, 0.25};
// Off the inputs, the field keeps at least this share of the lattice spacing
// from zero: a cut a rounding away from a vertex would make a tet of the
// zero set flat to rounding (and an input's vertex that the other input
// shares would be zero all along).
constexpr double kFieldFloor = 1e-3;
// The collar: the first and last slab are this share of a layer thick. At
// the collar the field is the end's off the input (each point keeps its
// side) and just positive on it: around every face, edge and vertex of the
// input at the end, the end slab's corners where the field is negative are
// then one connected set (the inside's), so the zero set, pinched onto the
// input there, stays a manifold.
constexpr double kCollar = 0.125;
// The slab joining the halves (the Delaunay fill) lasts this share of a
// layer: the field does not change across it.
constexpr double kFillSlab = 0.5;
// On the input, the collar's field is this share of the median circumradius
// of its faces, times 1 to 2 from vertex to vertex (order_the_collar): a
// planar quad's four vertices would otherwise make pieces of the zero set
// whose corners are cut at one time, flat, and a value near zero pieces a
// rounding wide. Small beside the blend's values on the input at the first
// layer, so that the zero set leaves the input early in the slab between:
// a lift of 1 % would keep it on a CAD part's large faces (flat_box_3) for
// most of that slab, and it would then cross the part's holes in a few
// frames.
constexpr double kCollarLift = 0.0025;
// The bridge's bump (lay_bridge), in lattice spacings: its radius, and how
// far below zero it takes the bump's core (where it is over kBridgeCore of
// its height) on the fill's layer; its segments go on kBridgeInto radii into
// the pieces they join; points within kBridgeReach radii of them may join
// the negative region where that makes a handle (preserve_topology).
constexpr double kBridgeRadius = 1.5;
constexpr double kBridgeDepth = 0.5;
constexpr double kBridgeCore = 0.5;
constexpr double kBridgeInto = 2.0;
constexpr double kBridgeReach = 2.0;

double size_of(const PointMatrix& A, const PointMatrix& B) {
  return std::max((A.colwise().maxCoeff() - A.colwise().minCoeff()).norm(),
                  (B.colwise().maxCoeff() - B.colwise().minCoeff()).norm());
}

double floored(double value, double floor) { return value < 0 ? std::min(value, -floor) : std::max(value, floor); }

// One input's half of the space-time triangulation, end first: its points
// (the conforming end's, then the refinement's), the cells of its stack, the
// times of its layers and the field at its points on each. The last layer
// is the fill's: its cells are the fill's end facet (the unrefined points).
struct Half {
  PointMatrix points;
  Index plain = 0;  // points the fill uses: the conforming end's
  RefinedCells refined;
  std::vector<double> times, weights;
  std::vector<Eigen::VectorXd> field;
  Index held = 0;  // values preserve_topology() held to their sign
};

// The times and blend weights of a half's layers, end first: the end, the
// collar, then every layer of the half up to the fill's (`m` of them).
void half_layers(Half& half, bool is_source, int m, int slabs, const BlendSchedule& schedule,
                 const MorphOptions& options) {
  const double range = options.t1 - options.t0;
  // The half's layers share the range up to the fill slab evenly.
  const double span = 0.5 - 0.5 * kFillSlab / slabs;
  const double collar = kCollar * span / m;
  std::vector<double> u{0.0, collar};
  for (int k = 1; k <= m; ++k) u.push_back(span * k / m);
  for (double at : u) {
    // The fill's layer has the middle's weight on both sides: the fill slab
    // joins two samplings of one field, and the shape moves in the stacks.
    const double w = at == u.back() ? schedule(0.5) : schedule(is_source ? at : 1.0 - at);
    if (!is_source) at = 1.0 - at;
    half.times.push_back(options.t0 + range * at), half.weights.push_back(w);
  }
}

// The field on each layer of a half, of the distances `s` to S and `t` to T
// (those through the inputs, build_half: of the signed distances' signs): at
// the end the input's own, exactly zero on it; at the collar the same off
// the input and a small positive lift on it (kCollar); then the blend
// (blend(), widened by `widening`).
void half_field(Half& half, const std::vector<bool>& on_surface, const SimplexMatrix& surface,
                const Eigen::VectorXd& s, const Eigen::VectorXd& t, double widening, bool is_source, double floor) {
  const Index n = static_cast<Index>(half.points.rows());
  const Eigen::VectorXd& own = is_source ? s : t;
  const Eigen::VectorXd radius = vertex_circumradius(half.points.topRows(half.plain), surface);
  auto zero = [&](Index v) { return v < half.plain && on_surface[v]; };
  std::vector<double> radii;
  for (Index v = 0; v < half.plain; ++v)
    if (zero(v)) radii.push_back(radius(v));
  std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2), radii.end());
  const double lift = radii.empty() ? floor : std::max(floor, kCollarLift * radii[radii.size() / 2]);
  Eigen::VectorXd end(n), collar(n);
  for (Index v = 0; v < n; ++v) {
    end(v) = zero(v) ? 0.0 : floored(own(v), floor);
    collar(v) = zero(v) ? lift : jittered(end(v), v, 0);
  }
  half.field = {end, collar};
  for (size_t layer = 2; layer < half.weights.size(); ++layer) {
    const double w = half.weights[layer];
    Eigen::VectorXd value(n);
    for (Index v = 0; v < n; ++v) value(v) = jittered(floored(blend(s(v), t(v), w, widening), floor), v, static_cast<int>(layer));
    half.field.push_back(value);
  }
}

// The collar's lift on the input, times 1 to 2 in the order of the
// points' values on the next layer (after preserve_topology). Between the
// collar and that layer, each prism is cut by the staircase (add_stack),
// which widens the solid where two neighbours' values swap order across the
// slab; lifts in any other order (a jitter, or the faces' own sizes) swap
// half the input's neighbours there, and the frames just after the end
// gained islands and handles a face wide on the input.
void order_the_collar(Half& half, const std::vector<bool>& on_surface) {
  std::vector<std::pair<double, Index>> order;
  for (Index v = 0; v < half.plain; ++v)
    if (on_surface[v]) order.emplace_back(half.field[2](v), v);
  std::sort(order.begin(), order.end());
  const double count = static_cast<double>(std::max<size_t>(order.size(), 1));
  for (size_t r = 0; r < order.size(); ++r) half.field[1](order[r].second) *= 1.0 + (static_cast<double>(r) + 0.5) / count;
}

// The rows of `more` that are neither a row of `points` nor an earlier row
// of `more`: points placed by rules (the middle of an edge, a point off a
// flat cell) on an input on a grid can land on the same spot twice, and the
// Delaunay triangulation refuses coinciding points.
PointMatrix without_points_already_there(const PointMatrix& points, const PointMatrix& more) {
  std::set<std::array<double, 3>> seen;
  for (Index r = 0; r < points.rows(); ++r) seen.insert({points(r, 0), points(r, 1), points(r, 2)});
  std::vector<Index> keep;
  for (Index r = 0; r < more.rows(); ++r)
    if (seen.insert({more(r, 0), more(r, 1), more(r, 2)}).second) keep.push_back(r);
  return more(keep, Eigen::all);
}

// Adds `more` to the end's points as free points and triangulates them
// again (`cells`), leaving out those inside the circumsphere of a refined
// face of the input the triangulation then misses (the clearance test of
// refinement_points() is for the nearest faces only): the fill must keep
// every refined face (Theorem 5.2.1). Returns how many were added.
Index add_free_points(EndMesh& end, PointMatrix more, SimplexMatrix& cells) {
  const Index n = static_cast<Index>(end.points.rows());
  more = without_points_already_there(end.points, more);
  if (more.rows() == 0) return 0;  // `cells` are the end's already
  for (int round = 0;; ++round) {
    PointMatrix points(n + more.rows(), 3);
    points << end.points.topRows(n), more;
    cells = delaunay_tetrahedra(points);
    const IndexVector missing = missing_facets(cells, end.constraints);
    if (missing.size() == 0 || more.rows() == 0 || round == kRefineRounds) {
      if (missing.size() != 0) more.resize(0, 3), cells = delaunay_tetrahedra(end.points.topRows(n));
      end.points.conservativeResize(n + more.rows(), 3);
      end.points.bottomRows(more.rows()) = more;
      end.on_surface.resize(end.points.rows(), false);
      return static_cast<Index>(more.rows());
    }
    std::vector<bool> drop(more.rows(), false);
    for (const Index f : missing) {
      const Eigen::Vector3d a = end.points.row(end.constraints(f, 0)), b = end.points.row(end.constraints(f, 1)),
                            c = end.points.row(end.constraints(f, 2));
      const Eigen::Vector3d ab = b - a, ac = c - a, normal = ab.cross(ac);
      const Eigen::Vector3d centre =
          a + (ac.squaredNorm() * normal.cross(ab) + ab.squaredNorm() * ac.cross(normal)) / (2 * normal.squaredNorm());
      const double radius = (centre - a).norm();
      for (Index r = 0; r < more.rows(); ++r)
        if ((Eigen::Vector3d(more.row(r)) - centre).norm() < 1.01 * radius) drop[r] = true;
    }
    std::vector<Index> keep;
    for (Index r = 0; r < more.rows(); ++r)
      if (!drop[r]) keep.push_back(r);
    more = PointMatrix(more(keep, Eigen::all));
  }
}

// The splits' points (the chords' and the curved edges' middles) take, on
// the layer before the fill's, the values the unsplit cells would have
// there (at their barycentric coordinates in the face each split): the
// slab to the fill, where they are not, then joins the same
// piecewise-linear field (morph_field_refine.cpp's transition_slab).
void slave_split_points(Half& half, Eigen::VectorXd& value) {
  for (size_t j = 0; j < half.refined.splits.size(); ++j) {
    double sum = 0;
    for (size_t k = 0; k < half.refined.splits[j].size(); ++k)
      sum += half.refined.shares[j][k] * value(half.refined.splits[j][k]);
    value(half.plain + static_cast<Index>(j)) = sum;
  }
}

// The signed distances to S and T at a conforming end's points: at its
// lattice points (rows `first` on, where conform_end() keeps its free points,
// unless moved since) those lattice_points() measured (`s`, `t`), the
// others measured here.
EndDistances end_distances(const PointMatrix& points, Index first, const PointMatrix& lattice,
                           const Eigen::VectorXd& s, const Eigen::VectorXd& t, const SignedDistance& dS,
                           const SignedDistance& dT) {
  const Index n = static_cast<Index>(points.rows());
  EndDistances out;
  out.s.resize(n), out.t.resize(n);
  std::vector<Index> unknown;
  for (Index r = 0; r < n; ++r) {
    const Index k = r - first;
    if (k >= 0 && k < lattice.rows() && points.row(r) == lattice.row(k)) {
      out.s(r) = s(k), out.t(r) = t(k);
    } else {
      unknown.push_back(r);
    }
  }
  const PointMatrix rest = points(unknown, Eigen::all);
  const Eigen::VectorXd rest_s = dS.distances(rest), rest_t = dT.distances(rest);
  for (size_t i = 0; i < unknown.size(); ++i)
    out.s(unknown[i]) = rest_s(static_cast<Index>(i)), out.t(unknown[i]) = rest_t(static_cast<Index>(i));
  return out;
}

// An end's tetrahedralization with its chords split, as build_half() splits
// them, with its points and the distances at them.
struct ChordsSplit {
  SimplexMatrix cells;
  PointMatrix points;
  EndDistances distances;
};

// The schedule measures the blend on these: on the end's cells alone, a thin
// part's inside (tets with only the input's points for corners) vanishes at
// the first weight past the end, and the schedule, reading that as fast
// motion, held the shape still for much of the range.
ChordsSplit chords_split(const EndMesh& end, const SimplexMatrix& cells, const EndDistances& distances,
                         const SignedDistance& own, const SignedDistance& dS, const SignedDistance& dT) {
  RefinedCells refined = split_chords(cells, end.points, end.on_surface, end.constraints, own);
  ChordsSplit out{std::move(refined.cells), PointMatrix(end.points.rows() + refined.new_points.rows(), 3), distances};
  out.points << end.points, refined.new_points;
  out.distances.extend(out.points, dS, dT);
  return out;
}

// Refines an end's points (`end`, its tetrahedralization `cells` and the
// distances at its points kept along) where the zero set needs it: beside
// flat cells, in the chords the fill would sample with the wrong sign, then
// in up to kRefineRounds rounds where the blend is sampled too coarsely;
// returns how many points were added.
Index refine_end(EndMesh& end, SimplexMatrix& cells, EndDistances& distances, const PointMatrix& V,
                 const SimplexMatrix& F, const SignedDistance& dS, const SignedDistance& dT, bool is_source, int m,
                 int slabs, const BlendSchedule& schedule, const MorphOptions& options, double spacing) {
  Half layers;
  half_layers(layers, is_source, m, slabs, schedule, options);
  layers.weights.pop_back();  // the fill's layer is sampled by the fill
  Index total = 0;
  // First the flat cells: a point that add_free_points() leaves out (it would
  // cost the input a face) is tried again nearer and farther.
  for (const double reach : kFlatCellReach) {
    const PointMatrix off_flat = points_off_flat_cells(cells, end.points, end.on_surface, reach);
    if (off_flat.rows() == 0) break;
    total += add_free_points(end, off_flat, cells);
    distances.extend(end.points, dS, dT);
  }
  // Then the chords the fill's end facet keeps unsplit, at the two layers
  // next to the fill (the stack's own points in them end at the layer before).
  const std::vector<double> next_to_fill{layers.weights.back(), schedule(0.5)};
  total += add_free_points(end, undersampled_chords(cells, end.points, end.on_surface, end.constraints,
                                                    is_source ? dS : dT, dS, dT, distances, next_to_fill, spacing),
                           cells);
  distances.extend(end.points, dS, dT);
  for (int round = 0; round < kRefineRounds; ++round) {
    const PointMatrix more = refinement_points(cells, end.points, end.on_surface, V, F, is_source ? dS : dT, dS, dT,
                                               distances, layers.weights, spacing);
    if (more.rows() == 0) break;
    const Index added = add_free_points(end, more, cells);
    distances.extend(end.points, dS, dT);
    total += added;
  }
  end.free_points += total;
  return total;
}

// A half from its conforming end and its cells in the fill: its chords
// split, with its layers and field: the blend of the distances through the
// inputs (distances_through_inputs, `spacing` the lattice's).
// `distances` holds those at the end's points, and gets the chords' middles'.
Half build_half(const EndMesh& end, const SimplexMatrix& cells, const SignedDistance& dS, const SignedDistance& dT,
                EndDistances& distances, bool is_source, int m, int slabs, const BlendSchedule& schedule,
                const MorphOptions& options, double floor, double spacing) {
  Half half;
  half_layers(half, is_source, m, slabs, schedule, options);
  half.refined = split_chords(cells, end.points, end.on_surface, end.constraints, is_source ? dS : dT);
  half.plain = static_cast<Index>(end.points.rows());
  half.points.resize(half.plain + half.refined.new_points.rows(), 3);
  half.points << end.points, half.refined.new_points;
  distances.extend(half.points, dS, dT);
  // The blend layers up to the one before the fill's, where the splits'
  // points are slaved to the unsplit cells (slave_split_points).
  const auto slaved_layer = static_cast<std::ptrdiff_t>(std::max<size_t>(half.weights.size(), 4) - 2);
  const std::vector<double> blend_weights(half.weights.begin() + 2, half.weights.begin() + slaved_layer);
  const std::vector<double> slaved_weights(half.weights.begin() + slaved_layer, half.weights.end());
  split_curved_edges(half.refined, end.points, end.on_surface, blend_weights, slaved_weights, dS, dT, distances,
                     kCurveTolerance * spacing, kCurveShortest * spacing, kCurveRounds);
  half.points.conservativeResize(half.plain + half.refined.new_points.rows(), 3);
  half.points.bottomRows(half.refined.new_points.rows()) = half.refined.new_points;
  Eigen::VectorXd s = distances.s, t = distances.t;
  distances_through_inputs(half.refined.cells, half.points, spacing, s, t);
  half_field(half, end.on_surface, end.constraints, s, t, distances.widening, is_source, floor);
  return half;
}

// The bridge (bridge_between_pieces of the blend at the middle) laid into a
// half's layers from the first blend layer on: the field is lowered by a
// bump around its segments, `radius` wide and deep enough to make them
// negative at the fill's layer, by a share growing evenly from the end to
// all of it there. Where the blend at the middle falls into more pieces
// than both ends have, both halves then grow the same necks towards the
// middle and meet in the fill with them; held values alone would keep
// whichever connection each half saw break last (a thread a thousandth of
// a cell thick), and the fill would trade one for the other at once. The
// bump is kept off both ends of each edge across a gap between the inputs
// (keep_gaps_open) and lifted where its zero would leave them
// (keep_bump_inside; no higher than -`floor`). Returns, per layer, the
// points the bump lowers (empty where none).
std::vector<std::vector<bool>> lay_bridge(Half& half, const EndDistances& distances, const OutsideBoth& outside_both,
                                          const Bridge& bridge, double radius, double depth, double floor) {
  const Index n = static_cast<Index>(half.points.rows());
  std::vector<std::vector<bool>> laid(half.field.size());
  if (bridge.segments.empty()) return laid;
  // The segments into the pieces go on into them, so that the neck reaches
  // them on layers where they are smaller than at the middle.
  std::vector<std::array<Eigen::Vector3d, 2>> segments = bridge.segments;
  for (size_t i = 0; i < bridge.segments.size(); ++i)
    if (bridge.into_piece[i]) {
      const auto& [p, q] = bridge.segments[i];
      segments.push_back({q, q + kBridgeInto * radius * (q - p).normalized()});
    }
  Eigen::VectorXd bump = Eigen::VectorXd::Zero(n);
  std::vector<bool> lowered(n, false);
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector3d x = half.points.row(v);
    double nearest = kBridgeReach * radius;
    for (const auto& [p, q] : segments) {
      const Eigen::Vector3d d = q - p;
      const double along = std::clamp((x - p).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      nearest = std::min(nearest, (p + along * d - x).norm());
    }
    if (nearest >= kBridgeReach * radius) continue;
    lowered[v] = true;
    // Outside both inputs the field stays positive (a shared hole stays empty).
    if (nearest >= radius || (distances.s(v) > 0 && distances.t(v) > 0)) continue;
    const double falloff = 1 - (nearest / radius) * (nearest / radius);
    bump(v) = falloff * falloff;
  }
  // Points the blend itself takes below zero on a blend layer: an edge from
  // one of them to a lowered point spans a gap as one between two lowered.
  std::vector<bool> negative(n, false);
  for (size_t layer = 2; layer < half.field.size(); ++layer)
    for (Index v = 0; v < n; ++v) negative[v] = negative[v] || half.field[layer](v) < 0;
  const std::vector<std::array<Index, 2>> edges = tet_edges(half.refined.cells);
  keep_gaps_open(half.points, edges, distances, outside_both, negative, bump);
  std::vector<Eigen::VectorXd> unbumped(half.field.begin(), half.field.end());
  for (size_t layer = 2; layer < half.field.size(); ++layer) {
    const double share = static_cast<double>(layer - 1) / static_cast<double>(half.field.size() - 2);
    Eigen::VectorXd& value = half.field[layer];
    // Deep enough that the bump's core is negative on this layer.
    double highest = 0;
    for (Index v = 0; v < n; ++v)
      if (bump(v) > kBridgeCore) highest = std::max(highest, value(v) / bump(v));
    value -= share * (highest + depth) * bump;
    laid[layer] = lowered;
  }
  for (size_t layer = 2; layer < half.field.size(); ++layer)
    keep_bump_inside(half.points, edges, distances, bump, half.field, layer, unbumped[layer], floor);
  return laid;
}

// Keeps a half's topology (preserve_topology) with the bridge laid in
// (lay_bridge), then slaves its chords' middles on the layer before the
// fill's. `least` and `most` are the ends' least and largest Betti numbers;
// `floor` the held values' (preserve_topology), `spacing` the lattice's.
void keep_topology(Half& half, const EndDistances& distances, const OutsideBoth& outside_both, const Bridge& bridge,
                   const std::array<Index, 3>& least, const std::array<Index, 3>& most, double floor, double spacing) {
  const std::vector<std::vector<bool>> laid =
      lay_bridge(half, distances, outside_both, bridge, kBridgeRadius * spacing, kBridgeDepth * spacing, floor);
  half.held = preserve_topology(half.refined.cells, half.field, 2, floor, least, most, laid);
  slave_split_points(half, half.field[half.field.size() - 2]);
}

// What the halves are made of beside the ends' cells.
struct HalfInputs {
  const EndMesh &source, &target;
  const SignedDistance &dS, &dT;
  int m, slabs;
  const BlendSchedule& schedule;
  const MorphOptions& options;
  double floor, spacing;
};

struct Halves {
  Half source, target;
};

// Both halves on the ends' cells, with their fields, before their
// topology is kept (keep_half_topology): what that needs of both.
struct HalvesToShape {
  Halves halves;
  EndDistances own[2];  // the distances at each half's points, its chords' middles included
  Bridge bridge;
  std::array<Index, 3> least, most;  // the ends' least and largest Betti numbers
};

// The halves on the ends' cells (`source_cells`, `target_cells`) with their
// fields, the ends' Betti numbers, and one bridge for both halves. `distances`
// (the ends' points') are copied: the chords' middles are each call's own.
HalvesToShape halves_to_shape(const HalfInputs& in, const SimplexMatrix& source_cells,
                              const SimplexMatrix& target_cells, const EndDistances (&distances)[2]) {
  HalvesToShape out{{}, {distances[0], distances[1]}, {}, {}, {}};
  out.halves.source = build_half(in.source, source_cells, in.dS, in.dT, out.own[0], true, in.m, in.slabs,
                                 in.schedule, in.options, in.floor, in.spacing);
  out.halves.target = build_half(in.target, target_cells, in.dS, in.dT, out.own[1], false, in.m, in.slabs,
                                 in.schedule, in.options, in.floor, in.spacing);
  std::array<Index, 3> betti[2];
  on_both_sides([&](int side) {
    const Half& half = side == 0 ? out.halves.source : out.halves.target;
    betti[side] = betti_numbers(half.refined.cells, half.field.front());
  });
  for (int i = 0; i < 3; ++i)
    out.least[i] = std::min(betti[0][i], betti[1][i]), out.most[i] = std::max(betti[0][i], betti[1][i]);
  // One bridge for both halves, found on the source's cells (the blend at
  // the middle is one function, sampled by either), so that both lay the
  // same necks.
  out.bridge = bridge_between_pieces(out.halves.source.refined.cells, out.halves.source.points,
                                     out.halves.source.field.back(), out.least[0]);
  return out;
}

// Keeps the topology of one half (0 the source's, 1 the target's): each
// half only sheds, from its end towards the middle, what the other end does
// not have. The two sides write nothing in common.
void keep_half_topology(HalvesToShape& shaping, int side, const HalfInputs& in) {
  const OutsideBoth outside_both = [&](const PointMatrix& points) -> Eigen::Array<bool, Eigen::Dynamic, 1> {
    return !in.dS.inside(points) && !in.dT.inside(points);
  };
  Half& half = side == 0 ? shaping.halves.source : shaping.halves.target;
  keep_topology(half, shaping.own[side], outside_both, shaping.bridge, shaping.least, shaping.most, in.floor,
                in.spacing);
  order_the_collar(half, (side == 0 ? in.source : in.target).on_surface);
}

// Both halves on the ends' cells, with their fields and their topology kept.
Halves shaped_halves(const HalfInputs& in, const SimplexMatrix& source_cells, const SimplexMatrix& target_cells,
                     const EndDistances (&distances)[2]) {
  HalvesToShape shaping = halves_to_shape(in, source_cells, target_cells, distances);
  on_both_sides([&](int side) { keep_half_topology(shaping, side, in); });
  return std::move(shaping.halves);
}

// Whether two tetrahedralizations have the same cells, in any order.
bool same_cells(const SimplexMatrix& a, const SimplexMatrix& b) {
  if (a.rows() != b.rows()) return false;
  auto sorted = [](const SimplexMatrix& cells) {
    std::vector<std::array<Index, 4>> rows(static_cast<size_t>(cells.rows()));
    for (Index c = 0; c < cells.rows(); ++c) {
      rows[c] = {cells(c, 0), cells(c, 1), cells(c, 2), cells(c, 3)};
      std::sort(rows[c].begin(), rows[c].end());
    }
    std::sort(rows.begin(), rows.end());
    return rows;
  };
  return sorted(a) == sorted(b);
}

// The certificate's cover checks of a half and its transition slab
// (morph_field.hpp's check_side_cover).
SideCover cover_of(const Half& half, const SimplexMatrix& transition) {
  return check_side_cover(half.points, half.plain, half.refined.cells, transition, half.times);
}

// What the certificate reads of a half (morph_field.hpp's SpaceTimeTriangulation).
SpaceTimeTriangulation::Side side_of(Half&& half, SimplexMatrix&& transition) {
  return {std::move(half.points), half.plain, std::move(half.refined.cells), std::move(transition),
          std::move(half.times)};
}

// Whether some point lies inside both inputs (both its distances negative).
bool inside_both(const EndDistances& distances) {
  return ((distances.s.array() < 0) && (distances.t.array() < 0)).any();
}

// The zero set of the field over the whole space-time triangulation: each
// half's stack and transition slab, then the fill's (add_fill). Each of the
// four parts has a builder of its own, so they can be extracted at once; the
// builders are joined in one order (a cut on an edge two parts share is the
// earlier one's), so the zero set is the same whichever part is extracted
// first. The parts need only the fill's end facets, which are the ends' own
// cells but for cospherical ties (field_morph), so they are extracted beside
// the fill's Delaunay triangulation.
class Extraction {
 public:
  // Its builders, appended in this order (the order the zero set's
  // vertices and pieces come in): the source's stack, its transition slab,
  // the target's transition slab, the target's stack, the fill. Each is
  // written by one call at a time; calls for different parts may run at once.
  enum Part { kSourceStack, kSourceTransition, kTargetTransition, kTargetStack, kFill, kParts };

  // `time_scale`: the shapes' size over the range (flat_to_rounding).
  Extraction(const Half& source, const Half& target, double time_scale)
      : source_(source), target_(target), nS_(static_cast<Index>(source.points.rows())),
        nT_(static_cast<Index>(target.points.rows())), JS_(static_cast<int>(source.times.size())),
        JT_(static_cast<int>(target.times.size())), target_base_(JS_ * nS_),
        zero_{ZeroSetBuilder(5, 4 * static_cast<size_t>(nS_)), ZeroSetBuilder(5, static_cast<size_t>(nS_)),
              ZeroSetBuilder(5, static_cast<size_t>(nT_)), ZeroSetBuilder(5, 4 * static_cast<size_t>(nT_)),
              ZeroSetBuilder(5, static_cast<size_t>(nS_ + nT_))},
        time_scale_(time_scale) {
    X_.resize(target_base_ + JT_ * nT_, 4);
    phi_.resize(X_.rows());
  }

  // Layers of the source go from its end (0) to the fill (JS-1); the
  // target's from the fill (0) to its end (JT-1).
  Index source_id(int layer, Index v) const { return layer * nS_ + v; }
  Index target_id(int layer, Index v) const { return target_base_ + layer * nT_ + v; }

  // Writes the source's layers: its field as it is then (its topology
  // kept), which the source's parts read. Only the source's rows.
  void place_source() {
    for (int j = 0; j < JS_; ++j) place(source_, j, source_id(j, 0));
  }
  // As place_source(), for the target.
  void place_target() {
    for (int j = 0; j < JT_; ++j) place(target_, JT_ - 1 - j, target_id(j, 0));
  }

  // The source's stack over its refined cells.
  void add_source_stack() {
    const SimplexMatrix& KS = source_.refined.cells;
    for (int j = 0; j + 2 < JS_; ++j) add_stack(KS, source_id(j, 0), source_id(j + 1, 0), kSourceStack);
  }
  // The slab from the source's stack to the fill's end facet `cells` (over
  // the source's unrefined points); sets source_transition.
  void add_source_transition(const SimplexMatrix& cells) {
    add_transition(cells, source_, [&](Index local) {
      return local < nS_ ? source_id(JS_ - 2, local) : source_id(JS_ - 1, local - nS_);
    }, true);
  }
  // The slab from the fill's end facet `cells` (over the target's unrefined
  // points) to the target's stack; sets target_transition.
  void add_target_transition(const SimplexMatrix& cells) {
    add_transition(cells, target_, [&](Index local) {
      return local < nT_ ? target_id(1, local) : target_id(0, local - nT_);
    }, false);
  }
  // The target's stack over its refined cells.
  void add_target_stack() {
    const SimplexMatrix& KT = target_.refined.cells;
    for (int j = 1; j + 1 < JT_; ++j) add_stack(KT, target_id(j, 0), target_id(j + 1, 0), kTargetStack);
  }

  // All of one side's, in turn.
  void add_source_stacks(const SimplexMatrix& cells) {
    place_source();
    add_source_stack();
    add_source_transition(cells);
  }
  void add_target_stacks(const SimplexMatrix& cells) {
    place_target();
    add_target_transition(cells);
    add_target_stack();
  }

  // The fill's 4-simplices (over the source's unrefined points, then the
  // target's), after both halves' parts, and the parts joined: the fill's
  // zero set is extracted while the halves' are joined, then joined last.
  void add_fill(const Fill& fill) {
    on_both_sides([&](int side) {
      if (side == 0) {
        for (int part = kSourceTransition; part < kFill; ++part) {
          zero_[kSourceStack].append(zero_[part]);
          zero_[part] = ZeroSetBuilder(5, 0);
        }
        return;
      }
      for (Index s = 0; s < fill.simplices.rows(); ++s) {
        Simplex4 simplex;
        for (int c = 0; c < 5; ++c) {
          const Index v = fill.simplices(s, c);
          simplex[c] = v < source_.plain ? source_id(JS_ - 1, v) : target_id(0, v - source_.plain);
        }
        add(simplex, kFill);
      }
    });
    zero_[kSourceStack].append(zero_[kFill]);
    zero_[kFill] = ZeroSetBuilder(5, 0);
  }

  // The zero set, once add_fill() has joined the halves'.
  Complex manifold() const {
    Complex out;
    const ZeroSetBuilder& zero = zero_[kSourceStack];
    const auto& cuts = zero.cuts();
    out.V.resize(static_cast<Index>(cuts.size()), 4);
    for (size_t c = 0; c < cuts.size(); ++c) {
      const ZeroCut& p = cuts[c];
      out.V.row(static_cast<Index>(c)) = p.a == p.b ? X_.row(p.a) : ((1 - p.s) * X_.row(p.a) + p.s * X_.row(p.b)).eval();
    }
    out.S = Eigen::Map<const SimplexMatrix>(zero.pieces().data(), static_cast<Index>(zero.piece_count()), 4);
    return out;
  }

  // The transition slabs in transition_slab()'s local ids, for the
  // certificate (SpaceTimeTriangulation).
  SimplexMatrix source_transition, target_transition;
  // The 4-simplices the zero set passes through that are flat but for rounding.
  Index flat_crossed() const {
    Index sum = 0;
    for (const Index n : flat_crossed_) sum += n;
    return sum;
  }

 private:
  // Layer `layer` of `half` (its own numbering, end first) at global `base`.
  void place(const Half& half, int layer, Index base) {
    const Index n = static_cast<Index>(half.points.rows());
    X_.middleRows(base, n) << half.points, Eigen::VectorXd::Constant(n, half.times[layer]);
    phi_.segment(base, n) = half.field[layer];
  }

  // Adds the zero set of `s` to builder `part`.
  void add(const Simplex4& s, int part) {
    std::array<double, 5> value;
    for (int c = 0; c < 5; ++c) value[c] = phi_(s[c]);
    ZeroSetBuilder& zero = zero_[part];
    const size_t pieces = zero.piece_count();
    zero.add(s.data(), value.data(), 0);
    if (zero.piece_count() != pieces && flat_to_rounding(X_, s, time_scale_)) ++flat_crossed_[part];
  }

  // Prisms over `cells` between two layers, skipping those the zero set
  // misses, each split by the staircase in staircase_rank()'s order.
  void add_stack(const SimplexMatrix& cells, Index bottom, Index top, int part) {
    std::array<Simplex4, 4> prism;
    const Index n = cells.maxCoeff() + 1;
    const std::vector<double> rank = staircase_rank(cells, phi_.segment(bottom, n), phi_.segment(top, n));
    for (Index c = 0; c < cells.rows(); ++c) {
      const Index* t = cells.row(c).data();
      bool negative = false, positive = false;
      for (int k = 0; k < 4; ++k) {
        (phi_(bottom + t[k]) < 0 ? negative : positive) = true;
        (phi_(top + t[k]) < 0 ? negative : positive) = true;
      }
      if (!negative || !positive) continue;
      prism_simplices(t, bottom, top, prism.data(), rank.data());
      for (const Simplex4& s : prism) add(s, part);
    }
  }

  template <class Global>
  void add_transition(const SimplexMatrix& cells, const Half& half, const Global& global, bool refined_at_bottom) {
    const Index n = static_cast<Index>(half.points.rows());
    // The staircase in the order add_stack() uses (staircase_rank), so that
    // this slab too only ever widens the solid (a neck kept by a bridge stays
    // joined), and not across the points held out of it.
    Eigen::VectorXd bottom(half.plain), top(half.plain);
    for (Index v = 0; v < half.plain; ++v) {
      const double refined = phi_(global(v)), plain = phi_(global(n + v));
      bottom(v) = refined_at_bottom ? refined : plain, top(v) = refined_at_bottom ? plain : refined;
    }
    const std::vector<double> rank = staircase_rank(cells, bottom, top);
    const std::vector<Simplex4> slab =
        transition_slab(cells, half.refined.splits, half.plain, n, refined_at_bottom, rank.data());
    SimplexMatrix& local = refined_at_bottom ? source_transition : target_transition;
    local.resize(static_cast<Index>(slab.size()), 5);
    for (size_t r = 0; r < slab.size(); ++r) {
      Simplex4 s = slab[r];
      for (int c = 0; c < 5; ++c) local(static_cast<Index>(r), c) = s[c];
      for (Index& v : s) v = global(v);
      add(s, refined_at_bottom ? kSourceTransition : kTargetTransition);
    }
  }

  const Half &source_, &target_;
  Index nS_, nT_;
  int JS_, JT_;
  Index target_base_;
  PointMatrix X_;
  Eigen::VectorXd phi_;
  ZeroSetBuilder zero_[kParts];
  double time_scale_;
  Index flat_crossed_[kParts] = {0, 0, 0, 0, 0};
};

// The tasks that follow the halves' lead in the fill stage
// (lead_and_beside): each half's topology kept, its transition slab and its
// stack extracted, and its covers checked for the certificate (its validity
// check, made here where a thread is free while the other fills).
std::vector<AfterTask> tasks_after_the_halves(HalvesToShape& shaping, const HalfInputs& in,
                                              std::optional<Extraction>& extraction,
                                              const SimplexMatrix (&cells)[2], std::array<SideCover, 2>& covers) {
  const Half &source = shaping.halves.source, &target = shaping.halves.target;
  // A priority only (the result is the same in any order): the target's
  // tasks first, whose chain was the longer on the shapes measured (the
  // target the larger shape).
  return {{[&] {
            keep_half_topology(shaping, 1, in);
            extraction->place_target();
          }},
          {[&] {
            keep_half_topology(shaping, 0, in);
            extraction->place_source();
          }},
          {[&] { extraction->add_target_transition(cells[1]); }, 0},
          {[&] {
             covers[1].transition =
                 check_transition_cover(target.points, target.plain, extraction->target_transition, target.times);
           },
           2},
          {[&] { extraction->add_target_stack(); }, 0},
          {[&] { extraction->add_source_transition(cells[0]); }, 1},
          {[&] {
             covers[0].transition =
                 check_transition_cover(source.points, source.plain, extraction->source_transition, source.times);
           },
           5},
          {[&] { extraction->add_source_stack(); }, 1},
          {[&] { covers[1].cells = check_cells_cover(target.points, target.refined.cells); }},
          {[&] { covers[0].cells = check_cells_cover(source.points, source.refined.cells); }}};
}

// The halves shaped again and extracted on the fill's end facets, where
// cospherical points broke their ties another way than the ends' own
// Delaunay cells (field_morph).
void extract_on_the_fills_cells(const HalfInputs& in, const Fill& fill, const EndDistances (&distances)[2],
                                double time_scale, Halves& halves, std::optional<Extraction>& extraction,
                                std::array<SideCover, 2>& covers) {
  extraction.reset();
  halves = shaped_halves(in, fill.source_cells, fill.target_cells, distances);
  extraction.emplace(halves.source, halves.target, time_scale);
  extraction->add_source_stacks(fill.source_cells);
  extraction->add_target_stacks(fill.target_cells);
  covers[0] = cover_of(halves.source, extraction->source_transition);
  covers[1] = cover_of(halves.target, extraction->target_transition);
}

// The flat cells a conforming end left that the free points beside them did not break.
Index flat_cells_left(const EndMesh& end, const SimplexMatrix& cells) {
  return points_off_flat_cells(cells, end.points, end.on_surface, 1.0).rows() / 2;
}

// Reports the input faces missing from the fill's end facets, and refuses a
// fill that misses any (Theorem 5.2.1).
void check_fill_conforms(const Fill& fill, const EndMesh& S, const EndMesh& T, MorphReport& report) {
  report.missing_source_faces = static_cast<Index>(missing_facets(fill.source_cells, S.constraints).size());
  report.missing_target_faces = static_cast<Index>(missing_facets(fill.target_cells, T.constraints).size());
  if (report.missing_source_faces || report.missing_target_faces)
    fail<MeshingError>("the space-time fill does not conform to the inputs (Theorem 5.2.1): ",
                       report.missing_source_faces, " source and ", report.missing_target_faces,
                       " target faces are missing");
}

}  // namespace

FieldMorph field_morph(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT, const SimplexMatrix& FT,
                       const MorphOptions& options, StageClock& clock) {
  if (VS.cols() != 3) fail<InputError>("the field method morphs 3D shapes (triangle meshes); use 'skeleton' for 2D");
  const int slabs = options.field_layers;
  if (slabs < 3 || slabs % 2 == 0) fail<InputError>("field_layers must be an odd number >= 3, got ", slabs);
  if (!(options.field_resolution >= 2)) fail<InputError>("field_resolution must be >= 2, got ", options.field_resolution);
  FieldMorph out;
  Morph& result = out.morph;
  MorphReport& report = result.report;
  const double size = std::max(size_of(VS, VT), 1e-300);

  clock.begin("free points", 0.05);
  const SignedDistance dS(VS, FS), dT(VT, FT);
  const Lattice lattice = lattice_points(VS, FS, dS, VT, FT, dT, size / options.field_resolution, size);
  auto with_shell = [](const PointMatrix& lattice_part, const PointMatrix& shell) {
    PointMatrix both(lattice_part.rows() + shell.rows(), 3);
    both << lattice_part, shell;
    return both;
  };
  const PointMatrix source_free = with_shell(lattice.source, surface_shell(VS, FS, dS));
  const PointMatrix target_free = with_shell(lattice.target, surface_shell(VT, FT, dT));

  clock.begin("conforming", 0.1);
  auto [S, T] = conform_ends({VS, FS, source_free}, {VT, FT, target_free}, lattice.corners, clock.while_waiting(),
                             options.mesher_time_limit);
  report.source_steiner_points = S.steiner_points, report.target_steiner_points = T.steiner_points;
  report.flat_cell_points = S.flat_cell_points + T.flat_cell_points;
  report.shared_points = share_coincident_points(S, T);
  report.source_conforming = report.target_conforming = true;

  clock.begin("schedule", 0.25);
  SimplexMatrix cells[2];
  EndDistances distances[2];
  ChordsSplit split[2];
  // The distances at the ends' points first, each end's on all threads: the
  // two ends' costs differ with their sizes, and what is left of each
  // side's work is shorter and serial.
  distances[0] = end_distances(S.points, VS.rows(), lattice.source, lattice.source_s, lattice.source_t, dS, dT);
  distances[1] = end_distances(T.points, VT.rows(), lattice.target, lattice.target_s, lattice.target_t, dS, dT);
  distances[0].widening = distances[1].widening = lattice.widening;
  on_both_sides([&](int side) {
    const EndMesh& end = side == 0 ? S : T;
    cells[side] = delaunay_tetrahedra(end.points);
    split[side] = chords_split(end, cells[side], distances[side], side == 0 ? dS : dT, dS, dT);
    // The schedule measures the blend the halves will have.
    distances_through_inputs(split[side].cells, split[side].points, lattice.spacing, split[side].distances.s,
                             split[side].distances.t);
  });
  report.inputs_apart = !inside_both(distances[0]) && !inside_both(distances[1]) && lattice.widening == 0;
  const BlendSchedule schedule = motion_schedule(VS, FS, VT, FT, split[0].cells, split[1].cells, split[0].points,
                                                 split[1].points, split[0].distances.s, split[0].distances.t,
                                                 split[1].distances.s, split[1].distances.t, kScheduleSamples,
                                                 lattice.widening);

  clock.begin("refinement", 0.3);
  const int m = (slabs - 1) / 2;
  Index added[2] = {0, 0};
  on_both_sides([&](int side) {
    const bool is_source = side == 0;
    added[side] = refine_end(is_source ? S : T, cells[side], distances[side], is_source ? VS : VT, is_source ? FS : FT,
                             dS, dT, is_source, m, slabs, schedule, options, lattice.spacing);
  });
  report.refinement_points = added[0] + added[1];
  report.flat_cells = flat_cells_left(S, cells[0]) + flat_cells_left(T, cells[1]);
  report.source_free_vertices = S.free_points, report.target_free_vertices = T.free_points;

  clock.begin("fill", 0.35);
  // The halves take their field and topology beside the fill (CGAL's, on
  // one thread), on the ends' own Delaunay cells: those are the fill's end
  // facets (Theorem 5.2.1) unless cospherical points break their ties
  // another way there, and then the halves are shaped again on the fill's.
  // What follows the halves (tasks_after_the_halves) goes to whichever
  // thread is free first, so that the thread the fill frees takes its share.
  const HalfInputs inputs{S, T, dS, dT, m, slabs, schedule, options, kFieldFloor * lattice.spacing,
                          lattice.spacing};
  const double time_scale = size / (options.t1 - options.t0);
  Fill fill;
  bool fill_has_ends_cells = false;
  HalvesToShape shaping;
  Halves& halves = shaping.halves;
  std::optional<Extraction> extraction;
  std::array<SideCover, 2>& covers = out.covers;
  lead_and_beside(
      [&] {
        shaping = halves_to_shape(inputs, cells[0], cells[1], distances);
        extraction.emplace(halves.source, halves.target, time_scale);
      },
      [&] {
        fill = fill_slab(S.points, T.points, lattice.spacing);
        check_fill_conforms(fill, S, T, report);
        fill_has_ends_cells = same_cells(fill.source_cells, cells[0]) && same_cells(fill.target_cells, cells[1]);
      },
      tasks_after_the_halves(shaping, inputs, extraction, cells, covers));
  report.fill_simplices = static_cast<Index>(fill.simplices.rows());
  if (!fill_has_ends_cells) extract_on_the_fills_cells(inputs, fill, distances, time_scale, halves, extraction, covers);
  for (const Half* half : {&halves.source, &halves.target})
    report.split_faces += static_cast<Index>(half->refined.splits.size());
  Half &source = halves.source, &target = halves.target;

  clock.begin("shape", 0.6);
  extraction->add_fill(fill);
  result.manifold = extraction->manifold();
  report.simplices = static_cast<Index>(result.manifold.S.rows());
  report.field_layers = slabs;
  report.lattice_spacing = lattice.spacing / size;
  report.middle_widening = lattice.widening / size;
  out.space_time = {side_of(std::move(source), std::move(extraction->source_transition)),
                    side_of(std::move(target), std::move(extraction->target_transition)),
                    extraction->flat_crossed()};
  return out;
}

}  // namespace animanifold
