// coordinate_bound.hpp: coordinates within the bound pass; the first row that is
// not finite or beyond it is named, a NaN among ordinary rows included.
#include "animanifold/coordinate_bound.hpp"
#include "animanifold/errors.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace animanifold;

namespace {

std::string refusal(const PointMatrix& points, double bound = kMaxCoordinate) {
  return fixtures::input_error_message([&] { check_coordinates(points, "vertex", bound); });
}

}  // namespace

TEST(CoordinateBound, PointsWithinTheBoundPassAnEmptySetToo) {
  PointMatrix points(3, 3);
  points << 0, 1, -1, kMaxCoordinate, -kMaxCoordinate, 0.5, 1e-300, 2, 3;
  EXPECT_NO_THROW(check_coordinates(points, "vertex"));
  EXPECT_NO_THROW(check_coordinates(PointMatrix(0, 3), "vertex"));
}

TEST(CoordinateBound, TheFirstRowBeyondTheBoundOrNotFiniteIsNamed) {
  PointMatrix points = PointMatrix::Ones(4, 3);
  points(2, 1) = -2e30;
  EXPECT_EQ(refusal(points), "vertex 2 has a coordinate of -2e+30, beyond +-1e+30");
  EXPECT_EQ(refusal(points, kMaxDerivedCoordinate), "(no InputError)");
  points(1, 2) = std::numeric_limits<double>::quiet_NaN();  // among ordinary rows: not skipped
  EXPECT_EQ(refusal(points, kMaxDerivedCoordinate), "vertex 1 is not finite");
  points(1, 2) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal(points), "vertex 1 is not finite");
}
