// The blend widened at the middle (blend, middle_widening in
// morph_field_internal.hpp): exact at the ends, zero where the inputs
// overlap well, and where they barely meet or lie apart, enough that the
// middle is half the thinner input's depth, holding no more than the
// larger input.
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

using namespace animanifold;
using namespace animanifold::morph_field;

namespace {

// Signed distances to two unit balls, centred at (-gap/2 - 1, 0, 0) and
// (gap/2 + 1, 0, 0), at the points of a regular grid over a box around
// both (each point standing for the same volume, as the lattice's
// candidates do); a negative gap makes them overlap.
struct TwoBalls {
  Eigen::VectorXd s, t;
};
TwoBalls two_balls(double gap, int cells = 40) {
  const double centre = 0.5 * gap + 1.0, reach = centre + 1.5;
  std::vector<double> s, t;
  for (int i = 0; i <= cells; ++i)
    for (int j = 0; j <= cells; ++j)
      for (int k = 0; k <= cells; ++k) {
        const Eigen::Vector3d p(-reach + 2 * reach * i / cells, -2.5 + 5.0 * j / cells, -2.5 + 5.0 * k / cells);
        s.push_back((p - Eigen::Vector3d(-centre, 0, 0)).norm() - 1.0);
        t.push_back((p - Eigen::Vector3d(centre, 0, 0)).norm() - 1.0);
      }
  return {Eigen::Map<Eigen::VectorXd>(s.data(), static_cast<Index>(s.size())),
          Eigen::Map<Eigen::VectorXd>(t.data(), static_cast<Index>(t.size()))};
}

Index inside_the_middle(const TwoBalls& balls, double widening) {
  Index count = 0;
  for (Index r = 0; r < balls.s.size(); ++r) count += blend(balls.s(r), balls.t(r), 0.5, widening) < 0;
  return count;
}

Index on_the_middles_zero_set(const TwoBalls& balls, double widening) {
  Index count = 0;
  for (Index r = 0; r < balls.s.size(); ++r) count += blend(balls.s(r), balls.t(r), 0.5, widening) == 0;
  return count;
}

}  // namespace

TEST(MorphFieldWidening, TheWidenedBlendIsEachInputsDistanceExactlyAtItsEnd) {
  for (const double widening : {0.0, 0.3, 7.0})
    for (const double s : {-0.25, 0.0, 1e-17, 3.5})
      for (const double t : {-2.0, 0.0, 0.125}) {
        EXPECT_EQ(blend(s, t, 0.0, widening), s);
        EXPECT_EQ(blend(s, t, 1.0, widening), t);
        EXPECT_DOUBLE_EQ(blend(s, t, 0.5, widening), 0.5 * (s + t) - widening);
      }
}

TEST(MorphFieldWidening, APointOutsideBothIsInsideAFrameOnlyWithinTheWideningOfOne) {
  const double widening = 0.4;
  for (const double s : {0.0, 0.1, 0.39, 0.41, 1.0, 3.0})
    for (const double t : {0.0, 0.2, 0.39, 0.41, 0.7, 5.0})
      for (int k = 0; k <= 100; ++k) {
        const double w = k / 100.0, value = blend(s, t, w, widening);
        if (std::min(s, t) > widening) EXPECT_GT(value, 0.0) << s << ", " << t << " at " << w;
      }
  // Within it, the middle takes in what lies within twice the widening of the two together.
  EXPECT_LT(blend(0.39, 0.39, 0.5, widening), 0.0);
  EXPECT_LT(blend(0.0, 0.7, 0.5, widening), 0.0);
  EXPECT_GT(blend(0.1, 0.71, 0.5, widening), 0.0);
}

TEST(MorphFieldWidening, InputsThatOverlapWellAreNotWidened) {
  const TwoBalls same = two_balls(-2.0);  // one ball twice
  EXPECT_EQ(middle_widening(same.s, same.t), 0.0);
  const TwoBalls overlapping = two_balls(-1.5);  // a quarter of a diameter apart
  EXPECT_EQ(middle_widening(overlapping.s, overlapping.t), 0.0);
}

TEST(MorphFieldWidening, InputsApartGetAMiddleThatHoldsAsMuchAsEitherAndNoMore) {
  for (const double gap : {0.1, 0.5, 1.2}) {
    const TwoBalls balls = two_balls(gap);
    const Index ball = (balls.s.array() < 0).count();
    ASSERT_GT(ball, 100);
    EXPECT_EQ(inside_the_middle(balls, 0.0), 0) << gap;  // the convex blend is empty there
    const double widening = middle_widening(balls.s, balls.t);
    ASSERT_GT(widening, 0.5 * gap) << gap;  // across the valley's floor, half the gap
    // All of them but those the widening puts on the zero set (zero counts
    // as outside; the grid's symmetric points tie).
    const Index held = inside_the_middle(balls, widening), tied = on_the_middles_zero_set(balls, widening);
    EXPECT_LE(tied, ball / 20) << gap;
    EXPECT_GE(held + tied, ball) << gap;
    // The depth asked for (half a ball's radius below the valley's floor)
    // would hold more than a ball: no more than the larger input holds (the
    // balls are alike; ties at the grid's symmetric points aside).
    EXPECT_LE(held, ball + ball / 10) << gap;
  }
}

TEST(MorphFieldWidening, AThinMiddleIsDeepenedToAShareOfTheThinnerInputsDepth) {
  // Two balls that overlap by a tenth of a diameter, the second's
  // distances capped at 0.05 deep (a thin input's): the middle is thin.
  const TwoBalls balls = two_balls(-0.2);
  Eigen::VectorXd slab = balls.t;
  for (Index r = 0; r < slab.size(); ++r) slab(r) = std::max(balls.t(r), -0.05);
  const double widening = middle_widening(balls.s, slab);
  const double thinner = std::min(-balls.s.minCoeff(), -slab.minCoeff());
  double deepest = 0;
  for (Index r = 0; r < slab.size(); ++r) deepest = std::max(deepest, -blend(balls.s(r), slab(r), 0.5, widening));
  EXPECT_GE(deepest, kMiddleDepth * thinner - 1e-12);
}

TEST(MorphFieldWidening, InputsFartherApartThanTheThinnersThicknessAreNotWidened) {
  for (const double gap : {2.5, 6.0}) {
    const TwoBalls balls = two_balls(gap);
    EXPECT_EQ(middle_widening(balls.s, balls.t), 0.0) << gap;
  }
}

TEST(MorphFieldWidening, NoInputInsideTheSamplesMeansNoWidening) {
  const Eigen::VectorXd outside = Eigen::VectorXd::Constant(10, 1.0), inside = Eigen::VectorXd::Constant(10, -1.0);
  EXPECT_EQ(middle_widening(outside, inside), 0.0);
  EXPECT_EQ(middle_widening(Eigen::VectorXd(), Eigen::VectorXd()), 0.0);
}
