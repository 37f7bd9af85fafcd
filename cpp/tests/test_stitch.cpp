// Stitching keyframes into a tetrahedral manifold (stitch.hpp).
#include "animanifold/errors.hpp"
#include "animanifold/stitch.hpp"

#include <gtest/gtest.h>

#include <cstdint>
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

TEST(Stitch, SizesBeyondThe32BitIndexAreRefusedBeforeAllocating) {
  // Counts only: nothing of this size is allocated.
  EXPECT_NO_THROW(check_stitch_size(2, 1000, 2000, 3));
  EXPECT_NO_THROW(check_stitch_size(2, 1073741823, 715827882, 3));  // 2^31-2 points, 2^31-2 simplices
  EXPECT_THROW(check_stitch_size(2, std::int64_t{1} << 31, 1, 3), InputError);        // points
  EXPECT_THROW(check_stitch_size(2, 4, 715827883, 3), InputError);                     // 3 * l = 2^31 + 1 simplices
  EXPECT_THROW(check_stitch_size(std::int64_t{1} << 40, 2, 1, 3), InputError);         // keyframes
  EXPECT_THROW(check_stitch_size(3, 2, std::int64_t{1} << 62, 3), InputError);         // a product past 64 bits
  EXPECT_EQ(stitched_simplex(2, 1000000000, 1000000000, 3), Eigen::Index{9000000000});
}

TEST(Stitch, AFaceAndItsReverseAreRefused) {
  StitchInput in = octahedron_animation();
  in.faces.conservativeResize(in.faces.rows() + 1, Eigen::NoChange);
  in.faces.row(in.faces.rows() - 1) << in.faces(5, 0), in.faces(5, 2), in.faces(5, 1);
  try {
    stitch(in);
    FAIL() << "a face and its reverse accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("faces 5 and 8 are one triangle in opposite orientations"), std::string::npos)
        << e.what();
  }
}

TEST(Stitch, TimesWhoseSpanOverflowsAreRefused) {
  StitchInput in = octahedron_animation();
  in.times << -1e308, 0, 1e308;
  EXPECT_THROW(stitch(in), InputError);
}
