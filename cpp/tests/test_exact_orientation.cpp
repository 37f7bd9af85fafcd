// Exact orientation signs and the scale-free relative volume of a simplex
// (exact_orientation.hpp, complex.hpp's relative_volume).
#include "animanifold/complex.hpp"
#include "animanifold/exact_orientation.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace animanifold {
namespace {

TEST(ExactOrientation, SignsOfFlatAndNearlyFlatSimplices) {
  PointMatrix P(4, 2);
  P << 0, 0, 1, 3, 2, 6, 2, std::nextafter(6.0, 7.0);
  const Index flat[3] = {0, 1, 2}, up[3] = {0, 1, 3}, down[3] = {1, 0, 3};
  EXPECT_EQ(exact_orientation(P, flat), 0);
  EXPECT_EQ(exact_orientation(P, up), 1);
  EXPECT_EQ(exact_orientation(P, down), -1);
  // The relative volume is scale-free: |det| over the longest edge squared, a right isosceles
  // corner's 1/2 however large.
  PointMatrix Q(3, 2);
  Q << 0, 0, 1e6, 0, 0, 1e6;
  const Index corner[3] = {0, 1, 2};
  EXPECT_NEAR(relative_volume(Q, corner), 0.5, 1e-12);
  EXPECT_EQ(relative_volume(P, flat), 0.0);
}

}  // namespace
}  // namespace animanifold
