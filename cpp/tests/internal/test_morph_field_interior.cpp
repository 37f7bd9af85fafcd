// The blend's distances through the inputs (distances_through_inputs,
// morph_field_internal.hpp): a limb of T that curls back beside S is as far
// from S as the path along it, so it retracts from its tip.
#include "animanifold/delaunay.hpp"
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

// A U-shaped limb in the plane (z in {0, 1}) on a unit grid: S is x <= 1; T is
// S and the limb, which runs along y <= 1 out to x = 8, up x = 7..8 to y = 5
// and back along y = 4..5 to x = 3, its tip two units from S across a gap
// (x = 2) outside T.
bool in_limb(double x, double y) {
  const bool bottom = y <= 1.0 && x <= 8.0;
  const bool side = x >= 7.0 && x <= 8.0 && y <= 5.0;
  const bool top = y >= 4.0 && y <= 5.0 && x >= 3.0 && x <= 8.0;
  return bottom || side || top;
}

struct Grid {
  PointMatrix points;
  Eigen::VectorXd s, t;
  Index at(int x, int y, int z) const { return (x * 7 + y) * 2 + z; }
};

Grid u_shaped_limb() {
  Grid g;
  g.points.resize(11 * 7 * 2, 3);
  g.s.resize(g.points.rows()), g.t.resize(g.points.rows());
  for (int x = 0; x <= 10; ++x)
    for (int y = 0; y <= 6; ++y)
      for (int z = 0; z <= 1; ++z) {
        const Index v = g.at(x, y, z);
        // A small jitter in the plane breaks the grid's cospherical ties;
        // each layer stays flat, so its hull faces join only neighbours.
        g.points.row(v) << x + 0.05 * jitter(x, y, z, 0), y + 0.05 * jitter(x, y, z, 1), z;
        g.s(v) = x - 1.0;  // the signed distance to x <= 1
        g.t(v) = x <= 1 || in_limb(x, y) ? -0.5 : 0.5;
      }
  return g;
}

}  // namespace

TEST(MorphFieldInterior, ALimbThatCurlsBackBesideTheSourceIsFartherFromItTheFartherAlongItsPath) {
  Grid g = u_shaped_limb();
  const SimplexMatrix cells = delaunay_tetrahedra(g.points);
  const Eigen::VectorXd s0 = g.s, t0 = g.t;
  const double spacing = 1.0;
  distances_through_inputs(cells, g.points, spacing, g.s, g.t);
  // Along the limb's inner side from its root to its tip: out along y = 1
  // to x = 7, up to y = 4, back to x = 3.
  std::vector<Index> along;
  for (int x = 2; x <= 7; ++x) along.push_back(g.at(x, 1, 0));
  for (int y = 2; y <= 4; ++y) along.push_back(g.at(7, y, 0));
  for (int x = 6; x >= 3; --x) along.push_back(g.at(x, 4, 0));
  // It never falls along the limb, and rises along the top, where the
  // straight distance falls towards the tip.
  const size_t top = along.size() - 5;  // (7, 4)
  for (size_t k = 1; k < along.size(); ++k) {
    EXPECT_GE(g.s(along[k]), g.s(along[k - 1])) << "point " << k << " along the limb";
    if (k > top) {
      EXPECT_LT(s0(along[k]), s0(along[k - 1]));
      EXPECT_GT(g.s(along[k]), g.s(along[k - 1])) << "point " << k << " along the limb's top";
    }
  }
  // The tip's inner corner: two units from S in a straight line, 13 along
  // the limb's inside (6 out, 3 up, 4 back), less the corners an edge
  // between two of the limb's points cuts (a cell's diagonal, 2 - sqrt 2 at
  // each turn) and the jitter.
  const Index tip = g.at(3, 4, 0);
  EXPECT_DOUBLE_EQ(s0(tip), 2.0);
  EXPECT_GE(g.s(tip), 13.0 - 2 * (2 - std::sqrt(2.0)) - 0.1 - kThroughSlack * spacing);
  // Beside the overlap the straight distance stands: the path there is no
  // longer than it by more than the slack.
  EXPECT_DOUBLE_EQ(g.s(g.at(2, 0, 0)), s0(g.at(2, 0, 0)));
  EXPECT_DOUBLE_EQ(g.s(g.at(5, 1, 0)), s0(g.at(5, 1, 0)));
  EXPECT_DOUBLE_EQ(g.s(g.at(3, 1, 1)), s0(g.at(3, 1, 1)));
  // Outside T, and inside both, nothing changes; nor does t, S lying inside T.
  for (Index v = 0; v < g.points.rows(); ++v) {
    if (t0(v) > 0 || s0(v) <= 0) EXPECT_EQ(g.s(v), s0(v)) << "point " << v;
    EXPECT_EQ(g.t(v), t0(v)) << "point " << v;
  }
}

TEST(MorphFieldInterior, APartOfOneInputThatDoesNotMeetTheOtherKeepsTheStraightDistance) {
  Grid g = u_shaped_limb();
  // S moved off to x <= -1: no grid point is inside both, so no path starts.
  for (Index v = 0; v < g.points.rows(); ++v) g.s(v) = g.points(v, 0) + 1.0;
  const Eigen::VectorXd s0 = g.s, t0 = g.t;
  distances_through_inputs(delaunay_tetrahedra(g.points), g.points, 1.0, g.s, g.t);
  EXPECT_EQ(g.s, s0);
  EXPECT_EQ(g.t, t0);
}
