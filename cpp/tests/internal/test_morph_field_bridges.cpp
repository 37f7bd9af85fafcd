// The field morph's bridges (morph_field_internal.hpp): the lowest paths
// between the pieces the blend falls into, the handle preserve_topology
// lets a bridge close so that the connection it replaces goes, and the lift
// that keeps a bridge's zero inside the inputs; and a thread
// preserve_topology held, released from its free end once it may go.
#include "animanifold/delaunay.hpp"
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

constexpr double kSpacing = 0.1;

// A jittered grid of kSpacing over [-1, 1]^3 and its Delaunay tetrahedra.
struct Grid {
  PointMatrix points;
  SimplexMatrix cells;
  Grid() {
    const int n = 21;
    points.resize(n * n * n, 3);
    Index row = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k, ++row)
          for (int axis = 0; axis < 3; ++axis)
            points(row, axis) = -1.0 + kSpacing * std::array<int, 3>{i, j, k}[axis] +
                                0.1 * kSpacing * jitter(i, j, k, axis);
    cells = delaunay_tetrahedra(points);
  }
};

double to_segment(const Eigen::Vector3d& x, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Eigen::Vector3d d = q - p;
  const double along = std::clamp((x - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p + along * d - x).norm();
}

double to_polyline(const Eigen::Vector3d& x, const std::vector<Eigen::Vector3d>& corners) {
  double nearest = INFINITY;
  for (size_t c = 0; c + 1 < corners.size(); ++c) nearest = std::min(nearest, to_segment(x, corners[c], corners[c + 1]));
  return nearest;
}

const Eigen::Vector3d kLeft(-0.5, 0, 0), kRight(0.5, 0, 0);

// Two balls of radius 0.25 at x = -+0.5, a speck (radius 0.06) at y = 0.8,
// and, when `rod_y` is given, a rod of radius 0.12 joining the balls round
// by y = rod_y: a signed distance, negative inside.
Eigen::VectorXd balls(const PointMatrix& points, const double* rod_y = nullptr) {
  Eigen::VectorXd field(points.rows());
  for (Index v = 0; v < points.rows(); ++v) {
    const Eigen::Vector3d x = points.row(v);
    double value = std::min({(x - kLeft).norm() - 0.25, (x - kRight).norm() - 0.25,
                             (x - Eigen::Vector3d(0, 0.8, 0)).norm() - 0.06});
    if (rod_y) {
      const std::vector<Eigen::Vector3d> rod{kLeft, {-0.5, *rod_y, 0}, {0.5, *rod_y, 0}, kRight};
      value = std::min(value, to_polyline(x, rod) - 0.12);
    }
    field(v) = value;
  }
  return field;
}

}  // namespace

TEST(MorphFieldBridges, TheLowestPathJoinsTheLastingPiecesAcrossTheirGapAndLeavesTheSpeck) {
  const Grid grid;
  const Eigen::VectorXd field = balls(grid.points);
  const Bridge bridge = bridge_between_pieces(grid.cells, grid.points, field, 1);
  ASSERT_FALSE(bridge.segments.empty());
  // The gap's lowest path runs along the x axis between the balls, where the
  // field rises to 0.25 at x = 0 (the grid's points, a jitter off the axis,
  // are a little higher).
  EXPECT_GT(bridge.height, 0.2);
  EXPECT_LT(bridge.height, 0.3);
  // It crosses the gap's middle (x = 0) near the axis, where the saddle is;
  // its ends in the pieces are in both balls; nothing goes to the speck.
  int into[2] = {0, 0}, crossings = 0;
  for (size_t s = 0; s < bridge.segments.size(); ++s) {
    const auto& [p, q] = bridge.segments[s];
    if (bridge.into_piece[s]) {
      ++into[q.x() > 0];
      EXPECT_LT(std::min((q - kLeft).norm(), (q - kRight).norm()), 0.25) << "segment " << s;
    }
    for (const Eigen::Vector3d& end : bridge.segments[s])
      EXPECT_GT((end - Eigen::Vector3d(0, 0.8, 0)).norm(), 0.3) << "segment " << s << " goes to the speck";
    if ((p.x() < 0) != (q.x() < 0)) {
      ++crossings;
      const Eigen::Vector3d middle = p + (q - p) * (-p.x() / (q.x() - p.x()));
      EXPECT_LE(std::hypot(middle.y(), middle.z()), 1.5 * kSpacing) << "segment " << s << " crosses off the axis";
    }
  }
  EXPECT_EQ(crossings, 1);
  EXPECT_GE(into[0], 1);
  EXPECT_GE(into[1], 1);
}

TEST(MorphFieldBridges, NoBridgeWhereThereAreNoMoreLastingPiecesThanAllowed) {
  const Grid grid;
  const Eigen::VectorXd field = balls(grid.points);
  EXPECT_TRUE(bridge_between_pieces(grid.cells, grid.points, field, 2).segments.empty());
  const double rod_y = 0.35;
  EXPECT_TRUE(bridge_between_pieces(grid.cells, grid.points, balls(grid.points, &rod_y), 1).segments.empty());
}

namespace {

// Three layers on the grid: two balls joined by a rod above (y = 0.35),
// then twice the same balls joined by a rod below (y = -0.35). The field
// moves the connection from one rod to the other. preserve_topology keeps
// at least one piece, and at most `most`'s Betti numbers where the points
// near the lower rod are the later layers' bridge (when `bridged`); the
// layers' Betti numbers after it.
struct MovedConnection {
  std::vector<Eigen::VectorXd> field;
  std::array<std::array<Index, 3>, 3> betti;
  std::vector<bool> lower_rod, upper_rod;  // the points along each rod's middle
};

MovedConnection move_the_connection(const Grid& grid, bool bridged, const std::array<Index, 3>& most) {
  const double above = 0.35, below = -0.35;
  MovedConnection out;
  out.field = {balls(grid.points, &above), balls(grid.points, &below), balls(grid.points, &below)};
  const Index n = grid.points.rows();
  out.lower_rod.assign(n, false), out.upper_rod.assign(n, false);
  std::vector<bool> near_lower_rod(n, false);
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector3d x = grid.points.row(v);
    out.lower_rod[v] = to_segment(x, {-0.4, below, 0}, {0.4, below, 0}) < 0.06;
    out.upper_rod[v] = to_segment(x, {-0.4, above, 0}, {0.4, above, 0}) < 0.06;
    near_lower_rod[v] = x.y() < 0 && to_polyline(x, {kLeft, {-0.5, below, 0}, {0.5, below, 0}, kRight}) < 0.2;
  }
  std::vector<std::vector<bool>> bridges(3);
  if (bridged) bridges[1] = bridges[2] = near_lower_rod;
  preserve_topology(grid.cells, out.field, 1, 1e-3 * kSpacing, {1, 0, 0}, most, bridges);
  for (int layer = 0; layer < 3; ++layer) out.betti[layer] = betti_numbers(grid.cells, out.field[layer]);
  return out;
}

// Whether every point of `part` is negative (true) or positive (false) in `field`.
bool all_of_sign(const Eigen::VectorXd& field, const std::vector<bool>& part, bool negative) {
  for (Index v = 0; v < field.size(); ++v)
    if (part[v] && (field(v) < 0) != negative) return false;
  return true;
}

}  // namespace

TEST(MorphFieldBridges, ABridgeClosesALoopWithinTheEndsBettiNumbersAndTheOldConnectionGoesAsAHandle) {
  const Grid grid;
  const MovedConnection moved = move_the_connection(grid, true, {1, 1, 0});
  EXPECT_EQ(moved.betti[0], (std::array<Index, 3>{2, 0, 0}));  // the balls with the rod above, and the speck
  // The lower rod closes the loop while the upper one still holds; a layer
  // on, the upper one goes.
  EXPECT_EQ(moved.betti[1][1], 1);
  EXPECT_TRUE(all_of_sign(moved.field[1], moved.lower_rod, true));
  EXPECT_EQ(moved.betti[2][1], 0);
  EXPECT_TRUE(all_of_sign(moved.field[2], moved.lower_rod, true));
  EXPECT_TRUE(all_of_sign(moved.field[2], moved.upper_rod, false));
  for (const auto& betti : moved.betti) EXPECT_EQ(betti[0], 2) << "a piece split off or joined";
}

TEST(MorphFieldBridges, WithoutABridgeOrAboveTheEndsBettiNumbersTheOldConnectionIsHeld) {
  const Grid grid;
  for (const bool bridged : {false, true}) {
    const MovedConnection moved = move_the_connection(grid, bridged, {1, 0, 0});
    for (const auto& betti : moved.betti) EXPECT_EQ(betti, (std::array<Index, 3>{2, 0, 0})) << bridged;
    EXPECT_FALSE(all_of_sign(moved.field[2], moved.upper_rod, false)) << bridged;
  }
}

namespace {

const Eigen::Vector3d kSmallCentre(0.3, 0, 0);

// The inputs' union at a point: negative inside the ball of radius 0.5 at the
// origin (the source) or the ball of radius 0.3 at kSmallCentre (the target).
double union_distance(const Eigen::Vector3d& x) {
  return std::min(x.norm() - 0.5, (x - kSmallCentre).norm() - 0.3);
}

// Where the zero of `field` crosses each edge whose ends differ in sign: the
// farthest such point from the inputs (union_distance), or -inf when none.
double farthest_crossing(const Grid& grid, const std::vector<std::array<Index, 2>>& edges,
                         const Eigen::VectorXd& field) {
  double farthest = -INFINITY;
  for (const auto& [a, b] : edges) {
    if ((field(a) < 0) == (field(b) < 0)) continue;
    const Eigen::Vector3d p = grid.points.row(a), q = grid.points.row(b);
    farthest = std::max(farthest, union_distance(p + (q - p) * (field(a) / (field(a) - field(b)))));
  }
  return farthest;
}

// Two balls of radius 0.4 with a gap 0.04 wide between them at x = 0.05,
// between two planes of the grid: the signed distances to each.
std::array<double, 2> distance_to(const Eigen::Vector3d& x) {
  const Eigen::Vector3d left(-0.37, 0, 0), right(0.47, 0, 0);
  return {(x - left).norm() - 0.4, (x - right).norm() - 0.4};
}

Eigen::Array<bool, Eigen::Dynamic, 1> outside_both_balls(const PointMatrix& points) {
  Eigen::Array<bool, Eigen::Dynamic, 1> outside(points.rows());
  for (Index i = 0; i < points.rows(); ++i) {
    const auto [s, t] = distance_to(points.row(i).transpose());
    outside(i) = s > 0 && t > 0;
  }
  return outside;
}

// The signed distances to the two balls at `points`, as the field morph keeps them.
EndDistances distances_to_balls(const PointMatrix& points) {
  EndDistances distances;
  distances.s.resize(points.rows()), distances.t.resize(points.rows());
  for (Index v = 0; v < points.rows(); ++v) {
    const auto [s, t] = distance_to(points.row(v).transpose());
    distances.s(v) = s, distances.t(v) = t;
  }
  return distances;
}

}  // namespace

TEST(MorphFieldBridges, ABumpIsLiftedSoThatItsZeroStaysInsideTheInputs) {
  const Grid grid;
  const Index n = grid.points.rows();
  EndDistances distances;
  distances.s.resize(n), distances.t.resize(n);
  Eigen::VectorXd blend(n), bump = Eigen::VectorXd::Zero(n);
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector3d x = grid.points.row(v);
    distances.s(v) = x.norm() - 0.5, distances.t(v) = (x - kSmallCentre).norm() - 0.3;
    blend(v) = 0.5 * (distances.s(v) + distances.t(v));
    if (union_distance(x) <= 0) bump(v) = 1;  // a bump over the whole of the inputs, as deep as a bridge's core
  }
  std::vector<Eigen::VectorXd> field{blend, blend - 2.0 * bump, blend};
  const std::vector<std::array<Index, 2>> edges = tet_edges(grid.cells);
  // Unlifted, the bump's zero lies most of an edge beyond the inputs: a
  // point of a shared hole there would be inside the frame.
  EXPECT_GT(farthest_crossing(grid, edges, field[1]), 0.5 * kSpacing);
  const Eigen::VectorXd bumped = field[1];
  keep_bump_inside(grid.points, edges, distances, bump, field, 1, blend, 1e-9);
  EXPECT_LE(farthest_crossing(grid, edges, field[1]), 1e-12);
  Index kept_deep = 0;
  for (Index v = 0; v < n; ++v) {
    if (bump(v) == 0) {
      EXPECT_EQ(field[1](v), blend(v)) << "point " << v << " is outside both inputs and was not lowered";
      continue;
    }
    // Lifted no higher than the blend, and still below zero inside an input.
    EXPECT_LE(field[1](v), blend(v)) << "point " << v;
    if (union_distance(grid.points.row(v)) < -1e-9) EXPECT_LT(field[1](v), 0) << "point " << v;
    kept_deep += field[1](v) == bumped(v);
  }
  // Points deeper inside than their edges are long keep all of the bump.
  EXPECT_GT(kept_deep, 0);
  EXPECT_EQ(field[0], blend);  // the layers beside it are only read
  EXPECT_EQ(field[2], blend);
}

TEST(MorphFieldBridges, NoEdgeBothOfWhoseEndsABumpLowersCrossesAGapBetweenTheInputs) {
  const Grid grid;
  const Index n = grid.points.rows();
  const EndDistances distances = distances_to_balls(grid.points);
  Eigen::VectorXd bump = Eigen::VectorXd::Zero(n);
  for (Index v = 0; v < n; ++v)
    if (distances.s(v) <= 0 || distances.t(v) <= 0) bump(v) = 1;
  const std::vector<std::array<Index, 2>> edges = tet_edges(grid.cells);
  const Eigen::VectorXd before = bump;
  EXPECT_GT(keep_gaps_open(grid.points, edges, distances, outside_both_balls, std::vector<bool>(n, false), bump), 0);
  // Sampled finely, every edge still lowered at both ends lies inside the balls.
  for (const auto& [a, b] : edges) {
    if (bump(a) <= 0 || bump(b) <= 0) continue;
    const Eigen::Vector3d p = grid.points.row(a), q = grid.points.row(b);
    for (int k = 0; k <= 100; ++k) {
      const auto [s, t] = distance_to(p + (q - p) * (k / 100.0));
      ASSERT_TRUE(s <= 1e-12 || t <= 1e-12) << "edge " << a << "-" << b << " crosses the gap, both ends lowered";
    }
  }
  // Only the gap's edges lose the bump: a point farther from it than an edge keeps it.
  for (Index v = 0; v < n; ++v)
    if (std::abs(grid.points(v, 0) - 0.05) > 0.2) EXPECT_EQ(bump(v), before(v)) << "point " << v;
}

TEST(MorphFieldBridges, NoEdgeFromABumpToTheBlendsOwnSolidCrossesAGapBetweenTheInputs) {
  const Grid grid;
  const Index n = grid.points.rows();
  // The balls with a gap between them; the bump lowers the left one only,
  // and the blend itself is below zero in the right one.
  const EndDistances distances = distances_to_balls(grid.points);
  Eigen::VectorXd bump = Eigen::VectorXd::Zero(n);
  std::vector<bool> negative(n, false);
  for (Index v = 0; v < n; ++v) {
    if (distances.s(v) <= 0) bump(v) = 1;
    if (distances.t(v) <= 0) negative[v] = true;
  }
  const std::vector<std::array<Index, 2>> edges = tet_edges(grid.cells);
  const auto crossing_gap = [&](const Eigen::VectorXd& lowered_by_bump) {
    Index count = 0;
    for (const auto& [a, b] : edges) {
      const bool bumped = lowered_by_bump(a) > 0 || lowered_by_bump(b) > 0;
      if (!bumped || !(lowered_by_bump(a) > 0 || negative[a]) || !(lowered_by_bump(b) > 0 || negative[b])) continue;
      const Eigen::Vector3d p = grid.points.row(a), q = grid.points.row(b);
      for (int k = 0; k <= 100; ++k) {
        const auto [s, t] = distance_to(p + (q - p) * (k / 100.0));
        if (s > 1e-12 && t > 1e-12) {
          ++count;
          break;
        }
      }
    }
    return count;
  };
  // Judged by the bump alone (no point of the right ball is bumped), every
  // such edge would keep it.
  Eigen::VectorXd bump_alone = bump;
  EXPECT_EQ(keep_gaps_open(grid.points, edges, distances, outside_both_balls, std::vector<bool>(n, false), bump_alone), 0);
  EXPECT_GT(crossing_gap(bump_alone), 0);
  EXPECT_GT(keep_gaps_open(grid.points, edges, distances, outside_both_balls, negative, bump), 0);
  EXPECT_EQ(crossing_gap(bump), 0);
  for (Index v = 0; v < n; ++v)
    if (std::abs(grid.points(v, 0) - 0.05) > 0.2) EXPECT_EQ(bump(v), bump_alone(v)) << "point " << v;
}

namespace {

const Eigen::Vector3d kBody(-0.7, 0, 0), kTip(0.75, 0, 0);

// A ball of radius 0.2 at kBody, with (when `with_tip`) a ball of radius 0.12
// at kTip and (when `with_rod`) a rod of radius 0.05 joining them along the
// x axis: a line of the grid's points, a thread. Without the rod, the field
// along its line is positive and rises towards the body.
Eigen::VectorXd body_rod_and_tip(const PointMatrix& points, bool with_rod, bool with_tip) {
  Eigen::VectorXd field(points.rows());
  for (Index v = 0; v < points.rows(); ++v) {
    const Eigen::Vector3d x = points.row(v);
    double value = (x - kBody).norm() - 0.2;
    if (with_tip) value = std::min(value, (x - kTip).norm() - 0.12);
    const double rod = to_segment(x, kBody, kTip) - 0.05;
    if (with_rod) value = std::min(value, rod);
    else if (rod < 0 && value > 0) value = 0.05 + 0.1 * (kTip.x() - x.x());
    field(v) = value;
  }
  return field;
}

}  // namespace

TEST(MorphFieldBridges, AThreadHeldToAPartThatThenVanishesRetractsFromItsFreeEndAndIsGoneByTheLastLayer) {
  const Grid grid;
  // The blend takes the rod out a layer before the tip: preserve_topology
  // holds it (the tip would split off). Once the tip has gone, the thread
  // is free from its end; judged one by one, root first (where the blend
  // rises), only its last point would leave each layer.
  std::vector<Eigen::VectorXd> field{body_rod_and_tip(grid.points, true, true),
                                     body_rod_and_tip(grid.points, false, true)};
  const int layers = 7;
  while (static_cast<int>(field.size()) < layers) field.push_back(body_rod_and_tip(grid.points, false, false));
  preserve_topology(grid.cells, field, 1, 1e-3 * kSpacing, {1, 0, 0}, {1, 0, 0},
                    std::vector<std::vector<bool>>(layers));
  std::vector<Index> thread(layers, 0);
  for (int layer = 0; layer < layers; ++layer) {
    EXPECT_EQ(betti_numbers(grid.cells, field[layer]), (std::array<Index, 3>{1, 0, 0})) << layer;
    for (Index v = 0; v < grid.points.rows(); ++v) {
      const Eigen::Vector3d x = grid.points.row(v);
      thread[layer] += field[layer](v) < 0 && x.x() > -0.45 && x.x() < 0.6 && x.tail<2>().norm() < 0.05;
    }
  }
  ASSERT_GE(thread[1], 9) << "the thread is held while the tip lasts";
  EXPECT_EQ(thread[layers - 1], 0) << "the thread is gone by the last layer";
  for (int layer = 2; layer < layers; ++layer) {
    EXPECT_LE(thread[layer], thread[layer - 1]) << "the thread only retracts, layer " << layer;
    EXPECT_LE(2 * (thread[layer - 1] - thread[layer]), thread[1] + 1)
        << "layer " << layer << " takes more than half the thread at once";
  }
}
