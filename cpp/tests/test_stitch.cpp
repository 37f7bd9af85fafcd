// Stitching keyframes into a tetrahedral manifold (stitch.hpp).
#include "animanifold/errors.hpp"
#include "animanifold/stitch.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "fixtures.hpp"

using namespace animanifold;
using fixtures::octahedron_animation;

TEST(Stitch, CountsAndConformity) {
  const Complex m = stitch(octahedron_animation());
  EXPECT_EQ(m.S.rows(), 3 * 8 * 2);
  EXPECT_EQ(m.V.rows(), 18);
  const auto report = check_manifold(m.S);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 16);
}

TEST(Stitch, ErrorsNameTheCulprit) {
  StitchInput in = octahedron_animation();
  in.times(2) = 0.4;
  try {
    stitch(in);
    FAIL() << "non-increasing times accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 2"), std::string::npos) << e.what();
  }
  in = octahedron_animation();
  in.frames(9, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(stitch(in), InputError);
}
