// Exact orientation signs and the scale-free relative volume of a simplex
// (exact_orientation.hpp, complex.hpp's relative_volume).
#include "animanifold/complex.hpp"
#include "animanifold/exact_orientation.hpp"

#include <gtest/gtest.h>

#include <CGAL/Epick_d.h>
#include <vector>

#include <Eigen/LU>
#include <cmath>
#include <cstdlib>

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

// CGAL's predicate alone, without the filter in front of it.
template <int D>
int cgal_sign(const PointMatrix& P) {
  using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
  std::vector<typename Kernel::Point_d> p;
  for (int i = 0; i <= D; ++i) p.emplace_back(P.row(i).data(), P.row(i).data() + D);
  const auto sign = Kernel().orientation_d_object()(p.begin(), p.end());
  return sign == CGAL::POSITIVE ? 1 : sign == CGAL::NEGATIVE ? -1 : 0;
}

// The filter in front of CGAL's predicate decides only signs it is sure of:
// on random simplices, on simplices exactly flat (the last corner an exact
// affine combination of two others: coordinates on a grid of 2^-20) and on
// those an ulp off flat, the sign is CGAL's.
TEST(ExactOrientation, TheFilterAgreesWithTheExactSignInEveryDimension) {
  std::srand(7);
  auto grid = [] { return std::ldexp(static_cast<double>(std::rand() % (1 << 20)) - (1 << 19), -20); };
  for (int D = 2; D <= 4; ++D) {
    PointMatrix P(D + 1, D);
    int flat = 0, decided_by_cgal_alone = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      for (Index r = 0; r <= D; ++r)
        for (int c = 0; c < D; ++c) P(r, c) = grid();
      if (trial % 3 != 0) {
        P.row(D) = 2 * P.row(1) - P.row(0);  // exact: on the line through corners 0 and 1
        if (trial % 3 == 2) P(D, trial % D) = std::nextafter(P(D, trial % D), 1.0);
      }
      const Index corners[5] = {0, 1, 2, 3, 4};
      const int expected = D == 2 ? cgal_sign<2>(P) : D == 3 ? cgal_sign<3>(P) : cgal_sign<4>(P);
      EXPECT_EQ(exact_orientation(P, corners), expected) << "D = " << D << ", trial " << trial;
      flat += expected == 0;
      decided_by_cgal_alone += trial % 3 == 2 && expected != 0;
    }
    EXPECT_EQ(flat, 1000) << "D = " << D;
    EXPECT_EQ(decided_by_cgal_alone, 1000) << "D = " << D << ": an ulp off flat is not flat";
  }
}

}  // namespace
}  // namespace animanifold
