// The order of a slab's staircase (staircase_rank, morph_field_internal.hpp):
// within a slab, the nodes the staircase puts on edges never cut the solid,
// and take it across a point outside it on both layers only where that
// point has neighbours that join and others that leave.
#include "animanifold/delaunay.hpp"
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

// A point's field at share s of the slab, each point interpolated in time.
double at(const Eigen::VectorXd& bottom, const Eigen::VectorXd& top, Index v, double s) {
  return (1 - s) * bottom(v) + s * top(v);
}

struct Mismatches {
  Index across_held = 0;  // negative between two positive ends, one positive on both layers
  Index cutting = 0;      // positive between two negative ends
};

// The edges (i, j) of `cells`, i before j in the order `rank` (ties by id, as
// prism_simplices), whose staircase node at share s, (1 - s) bottom_i +
// s top_j, has a sign other than both ends' when those agree (s sampled),
// counted once per edge.
Mismatches mismatches(const SimplexMatrix& cells, const Eigen::VectorXd& bottom, const Eigen::VectorXd& top,
                      const std::vector<double>& rank) {
  const auto before = [&](Index a, Index b) { return rank[a] != rank[b] ? rank[a] < rank[b] : a < b; };
  const auto positive_throughout = [&](Index v) { return bottom(v) >= 0 && top(v) >= 0; };
  Mismatches out;
  for (const auto& edge : tet_edges(cells)) {
    const Index i = before(edge[0], edge[1]) ? edge[0] : edge[1], j = i == edge[0] ? edge[1] : edge[0];
    for (int k = 1; k < 100; ++k) {
      const double s = k / 100.0, node = (1 - s) * bottom(i) + s * top(j);
      const bool a = at(bottom, top, i, s) < 0, b = at(bottom, top, j, s) < 0;
      if (a != b || (node < 0) == a) continue;
      if (a) ++out.cutting;
      else if (positive_throughout(i) || positive_throughout(j)) ++out.across_held;
      else continue;  // widened between two points that cross: allowed
      break;
    }
  }
  return out;
}

}  // namespace

TEST(MorphFieldStaircase, APointHeldOutsideBetweenJoiningNeighboursComesLastAndBetweenLeavingOnesFirst) {
  const SimplexMatrix cell = (SimplexMatrix(1, 4) << 0, 1, 2, 3).finished();
  // Point 0 is held just above zero on both layers (preserve_topology's
  // kHeldOutside floors); the others join the solid, or leave it.
  const Eigen::VectorXd held_bottom = (Eigen::VectorXd(4) << 3e-4, 0.5, 0.4, 0.6).finished();
  const Eigen::VectorXd joined_top = (Eigen::VectorXd(4) << 3e-4, -0.5, -0.6, -0.4).finished();
  std::vector<double> rank = staircase_rank(cell, held_bottom, joined_top);
  for (const Index v : {1, 2, 3}) EXPECT_LT(rank[v], rank[0]) << "joining point " << v;
  EXPECT_EQ(mismatches(cell, held_bottom, joined_top, rank).across_held, 0);
  // In the order of decrease alone it comes first, and the solid reaches
  // across it before its neighbours join.
  const std::vector<double> decrease{0.0, 1.0, 1.0, 1.0};
  EXPECT_GT(mismatches(cell, held_bottom, joined_top, decrease).across_held, 0);

  Eigen::VectorXd leaving_bottom = -held_bottom, leaving_top = -joined_top;
  leaving_bottom(0) = leaving_top(0) = 3e-4;
  rank = staircase_rank(cell, leaving_bottom, leaving_top);
  for (const Index v : {1, 2, 3}) EXPECT_GT(rank[v], rank[0]) << "leaving point " << v;
  EXPECT_EQ(mismatches(cell, leaving_bottom, leaving_top, rank).across_held, 0);
  EXPECT_GT(mismatches(cell, leaving_bottom, leaving_top, std::vector<double>{0.0, -1.0, -1.0, -1.0}).across_held, 0);
}

TEST(MorphFieldStaircase, OnARandomSlabTheStaircaseNeverCutsTheSolidAndReachesAcrossFewerHeldPoints) {
  // A jittered grid, a ball of field that moves sideways across the slab,
  // and a plane of points held just above zero on both layers that it meets
  // on one side (joining) and leaves on the other.
  const int n = 9;
  PointMatrix points(n * n * n, 3);
  Index row = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++row)
        for (int axis = 0; axis < 3; ++axis)
          points(row, axis) = std::array<int, 3>{i, j, k}[axis] / (n - 1.0) + 0.02 * jitter(i, j, k, axis);
  const SimplexMatrix cells = delaunay_tetrahedra(points);
  Eigen::VectorXd bottom(points.rows()), top(points.rows());
  std::vector<Index> held;
  for (Index v = 0; v < points.rows(); ++v) {
    const Eigen::Vector3d x = points.row(v);
    bottom(v) = (x - Eigen::Vector3d(0.35, 0.5, 0.5)).norm() - 0.3;
    top(v) = (x - Eigen::Vector3d(0.65, 0.5, 0.5)).norm() - 0.3;
    if (std::abs(x.y() - 0.5) < 0.07 && x.x() > 0.45 && x.x() < 0.55) {
      bottom(v) = top(v) = 3e-4 * (1 + 0.1 * jitter(v, 0, 0, 0));
      held.push_back(v);
    }
  }
  ASSERT_FALSE(held.empty());
  const std::vector<double> rank = staircase_rank(cells, bottom, top);
  std::vector<double> decrease(points.rows());
  for (Index v = 0; v < points.rows(); ++v) decrease[v] = bottom(v) - top(v);
  const Mismatches plain = mismatches(cells, bottom, top, decrease), ranked = mismatches(cells, bottom, top, rank);
  EXPECT_GT(plain.across_held, 0);   // the order of decrease reaches across the held points
  EXPECT_EQ(plain.cutting, 0);       // and never cuts
  EXPECT_EQ(ranked.cutting, 0);      // nor does the staircase's order
  EXPECT_LT(ranked.across_held, plain.across_held);
}
