#include "morph_skeleton.hpp"

#include "fixtures.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace animanifold;

namespace {

// A torus around z (radii 1 and 0.3, 24 x 12 quads split in two, outward):
// its hull's flat discs at z = ±0.3 lie over the hole.
void torus(PointMatrix& V, SimplexMatrix& F) {
  const int major = 24, minor = 12;
  V.resize(major * minor, 3);
  F.resize(2 * major * minor, 3);
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const double u = 2 * M_PI * i / major, w = 2 * M_PI * j / minor;
      V.row(i * minor + j) << (1 + 0.3 * std::cos(w)) * std::cos(u), (1 + 0.3 * std::cos(w)) * std::sin(u), 0.3 * std::sin(w);
    }
  int f = 0;
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const Index a = i * minor + j, b = ((i + 1) % major) * minor + j, c = ((i + 1) % major) * minor + (j + 1) % minor,
                  d = i * minor + (j + 1) % minor;
      F.row(f++) << a, b, c;
      F.row(f++) << a, c, d;
    }
}

}  // namespace

TEST(HullCaps, OnePointOverEachDiscOfATorusBelowTheHullsOtherPlanes) {
  PointMatrix V;
  SimplexMatrix F;
  torus(V, F);
  const PointMatrix caps = hull_cap_points(V, F);
  ASSERT_EQ(caps.rows(), 2);
  const Index top = caps(0, 2) > 0 ? 0 : 1;
  for (const Index r : {top, 1 - top}) {
    EXPECT_NEAR(caps(r, 0), 0.0, 1e-6);  // over the disc's centre
    EXPECT_NEAR(caps(r, 1), 0.0, 1e-6);
    EXPECT_GT(std::abs(caps(r, 2)) - 0.3, 1e-2 * 2.6);  // outside the hull, not in a sliver with the disc
  }
  EXPECT_GT(caps(top, 2), 0.3);
  EXPECT_LT(caps(1 - top, 2), -0.3);
  // Below the plane of every face of the torus on its hull: the points see
  // only their discs, so their hull faces end at the discs' rims.
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    double highest = -1;
    for (Index v = 0; v < V.rows(); ++v) highest = std::max(highest, n.dot(Eigen::Vector3d(V.row(v).transpose()) - a));
    if (highest > 1e-12) continue;  // not a face on the hull
    for (Index r = 0; r < 2; ++r) EXPECT_LT(n.dot(Eigen::Vector3d(caps.row(r).transpose()) - a), 0.0) << "face " << f;
  }
}

TEST(HullCaps, NoneForConvexShapesOrFlatSidesOfTheShapeItself) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  EXPECT_EQ(hull_cap_points(V, F).rows(), 0);
  // A cube's squares are flat sides of its hull made of its own faces.
  PointMatrix C(8, 3);
  for (int i = 0; i < 8; ++i) C.row(i) << (i & 1 ? 1 : -1), (i & 2 ? 1 : -1), (i & 4 ? 1 : -1);
  SimplexMatrix Q(12, 3);
  Q << 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5;
  EXPECT_EQ(hull_cap_points(C, Q).rows(), 0);
}

TEST(HullCaps, TheSamePointsWhateverTheOrderOfThePoints) {
  // CGAL's hull triangulates a flat disc one way or another (by the order
  // of its points; under bpy, from one call to the next): the sums over its
  // triangles round differently, and a cap point one unit in the last place
  // off is perturbed quite otherwise (the same morph came out different).
  // The points are put on a grid, so none of that shows.
  PointMatrix V;
  SimplexMatrix F;
  torus(V, F);
  const PointMatrix first = hull_cap_points(V, F);
  const Index n = V.rows();
  PointMatrix reversed = V.colwise().reverse();
  SimplexMatrix renumbered = F;
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) renumbered(f, c) = n - 1 - F(f, c);
  const PointMatrix again = hull_cap_points(reversed, renumbered);
  ASSERT_EQ(first.rows(), 2);
  ASSERT_EQ(again.rows(), 2);
  const Index top = first(0, 2) > 0 ? 0 : 1, top_again = again(0, 2) > 0 ? 0 : 1;
  EXPECT_TRUE((first.row(top).array() == again.row(top_again).array()).all());
  EXPECT_TRUE((first.row(1 - top).array() == again.row(1 - top_again).array()).all());
}
