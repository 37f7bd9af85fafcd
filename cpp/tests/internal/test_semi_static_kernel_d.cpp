// The Delaunay traits of delaunay_exact() (semi_static_kernel_d.hpp) answer
// as Epick_d does, on general points and on the degenerate ones the field
// method's fill is made of: two layers in time sharing points, lattices
// with cospherical cells.
#include "semi_static_kernel_d.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

namespace animanifold {
namespace {

template <int D>
using Point = typename SemiStaticKernel<D>::Point_d;

// Points of two layers (time 0 and 0.25) of a lattice of spacing 0.1 in
// space, with a few off it, so that cells of both layers and across are
// cospherical and many orientations vanish.
template <int D>
std::vector<Point<D>> layered_lattice(std::mt19937_64& random) {
  std::uniform_int_distribution<int> step(0, 3);
  std::uniform_real_distribution<double> off(-0.5, 0.5);
  std::vector<Point<D>> points;
  for (int k = 0; k < 60; ++k) {
    std::array<double, D> x;
    for (int c = 0; c + 1 < D; ++c) x[c] = 0.1 * step(random) + (k % 5 == 0 ? 0.01 * off(random) : 0.0);
    x[D - 1] = k % 2 ? 0.25 : 0.0;
    points.emplace_back(x.begin(), x.end());
  }
  return points;
}

template <int D>
std::vector<Point<D>> general(std::mt19937_64& random) {
  std::uniform_real_distribution<double> coordinate(-1, 1);
  std::vector<Point<D>> points;
  for (int k = 0; k < 60; ++k) {
    std::array<double, D> x;
    for (double& v : x) v = coordinate(random);
    points.emplace_back(x.begin(), x.end());
  }
  return points;
}

// Compares `trials` random orientations and in-sphere tests of `points`;
// returns how many of Epick_d's answers were zero.
template <int D>
int expect_the_answers_of_epick_d(const std::vector<Point<D>>& points, std::mt19937_64& random, int trials) {
  const SemiStaticKernel<D> kernel;
  const CGAL::Epick_d<CGAL::Dimension_tag<D>> epick;
  const auto orientation = kernel.orientation_d_object();
  const auto side = kernel.side_of_oriented_sphere_d_object();
  const auto epick_orientation = epick.orientation_d_object();
  const auto epick_side = epick.side_of_oriented_sphere_d_object();
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  int zeros = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<Point<D>> simplex;
    for (int k = 0; k <= D; ++k) simplex.push_back(points[pick(random)]);
    const CGAL::Orientation expected_orientation = epick_orientation(simplex.begin(), simplex.end());
    EXPECT_EQ(orientation(simplex.begin(), simplex.end()), expected_orientation) << "trial " << trial;
    const Point<D>& query = points[pick(random)];
    const CGAL::Oriented_side expected_side = epick_side(simplex.begin(), simplex.end(), query);
    EXPECT_EQ(side(simplex.begin(), simplex.end(), query), expected_side) << "trial " << trial;
    zeros += (expected_orientation == CGAL::ZERO) + (expected_side == CGAL::ON_ORIENTED_BOUNDARY);
  }
  return zeros;
}

TEST(SemiStaticKernelD, AnswersAsEpickDOnGeneralPoints) {
  std::mt19937_64 random(5);
  expect_the_answers_of_epick_d<3>(general<3>(random), random, 20000);
  expect_the_answers_of_epick_d<4>(general<4>(random), random, 20000);
}

TEST(SemiStaticKernelD, AnswersAsEpickDOnLayeredLatticesWhereManyAnswersAreZero) {
  std::mt19937_64 random(9);
  // A share of zeros: the degenerate answers are met, not only the general ones.
  EXPECT_GT(expect_the_answers_of_epick_d<3>(layered_lattice<3>(random), random, 20000), 2000);
  EXPECT_GT(expect_the_answers_of_epick_d<4>(layered_lattice<4>(random), random, 20000), 2000);
}

}  // namespace
}  // namespace animanifold
