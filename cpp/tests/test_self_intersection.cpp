// Crossing faces of a surface or a polygon (self_intersection.hpp).
#include "animanifold/self_intersection.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <utility>

#include "fixtures.hpp"

namespace animanifold {
namespace {

TEST(SelfIntersection, FindsCrossingFacesAndNotNeighbours) {
  PointMatrix V, two(12, 3);
  SimplexMatrix F, both(16, 3);
  fixtures::octahedron(V, F);
  EXPECT_TRUE(self_intersections(V, F).empty());
  two << V, V.rowwise() + Eigen::RowVector3d(0.5, 0.2, 0.1);
  both << F, F.array() + 6;
  const auto pairs = self_intersections(two, both, 0);
  ASSERT_FALSE(pairs.empty());
  for (const auto& [a, b] : pairs) EXPECT_TRUE(a < 8 && b >= 8);  // one face of each copy
  // 2D: a pentagram's edges cross; a pentagon's do not.
  PointMatrix star(5, 2), gon(5, 2);
  SimplexMatrix loop(5, 2);
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * M_PI * i / 5, b = 2 * M_PI * ((2 * i) % 5) / 5;
    gon.row(i) << std::cos(a), std::sin(a);
    star.row(i) << std::cos(b), std::sin(b);
    loop.row(i) << i, (i + 1) % 5;
  }
  EXPECT_TRUE(self_intersections(gon, loop).empty());
  EXPECT_FALSE(self_intersections(star, loop).empty());
}

TEST(SelfIntersection, ATolerancePassesRoundingButNotCrossings) {
  // Two triangles of a closed shape's worth (only the pair matters): one pierces the other by
  // `depth` along z.
  auto pierced = [](double depth) {
    PointMatrix V(6, 3);
    V << 0, 0, 0, 2, 0, 0, 0, 2, 0,  // in z = 0
        0.5, 0.5, -depth, 0.6, 0.5, 1, 0.5, 0.6, 1;  // one corner below it
    SimplexMatrix F(2, 3);
    F << 0, 1, 2, 3, 4, 5;
    return std::make_pair(V, F);
  };
  const auto [shallow, shallow_faces] = pierced(1e-13);
  EXPECT_EQ(self_intersections(shallow, shallow_faces, 0).size(), 1u);        // the exact test finds it
  EXPECT_TRUE(self_intersections(shallow, shallow_faces, 0, 1e-9).empty());  // rounding: left out
  const auto [deep, deep_faces] = pierced(0.1);
  EXPECT_EQ(self_intersections(deep, deep_faces, 0, 1e-9).size(), 1u);
  // Two triangles in one plane overlapping over a wide region: a fold, whatever the tolerance.
  PointMatrix V(6, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0, 2.5, 0.5, 0, 0.5, 2.5, 0;
  SimplexMatrix F(2, 3);
  F << 0, 1, 2, 3, 4, 5;
  EXPECT_EQ(self_intersections(V, F, 0, 1e-9).size(), 1u);
  // ... and barely overlapping (a sliver 1e-13 wide): rounding.
  V.row(3) << 1 - 1e-13, 1 - 1e-13, 0;
  V.row(4) << 3, 0, 0;
  V.row(5) << 0, 3, 0;
  EXPECT_EQ(self_intersections(V, F, 0).size(), 1u);
  EXPECT_TRUE(self_intersections(V, F, 0, 1e-9).empty());
}

}  // namespace
}  // namespace animanifold
