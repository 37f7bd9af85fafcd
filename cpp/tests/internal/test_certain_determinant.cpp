// The semi-static determinant filter (certain_determinant.hpp): where it
// gives a sign, the sign is the exact one (rational arithmetic decides);
// on well-conditioned matrices it gives one; exact zero columns are zero;
// a lifted column that underflowed is never taken for one.
#include "certain_determinant.hpp"

#include <gtest/gtest.h>

#include <gmpxx.h>

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <utility>

namespace animanifold {
namespace {

template <int N>
using Matrix = std::array<std::array<double, N>, N>;

// The exact sign of det(m) over the rationals (Gaussian elimination).
template <int N>
int exact_sign(const Matrix<N>& m) {
  std::array<std::array<mpq_class, N>, N> a;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) a[r][c] = m[r][c];
  int sign = 1;
  for (int c = 0; c < N; ++c) {
    int pivot = c;
    while (pivot < N && a[pivot][c] == 0) ++pivot;
    if (pivot == N) return 0;
    if (pivot != c) std::swap(a[pivot], a[c]), sign = -sign;
    if (a[c][c] < 0) sign = -sign;
    for (int r = c + 1; r < N; ++r) {
      const mpq_class factor = a[r][c] / a[c][c];
      for (int k = c; k < N; ++k) a[r][k] -= factor * a[c][k];
    }
  }
  return sign;
}

// Points' differences to a query, lifted: the in-sphere matrix of
// semi_static_kernel_d.hpp, from `points` (N rows of N - 1 coordinates).
template <int N>
Matrix<N> lifted(const std::array<std::array<double, N - 1>, N>& points, const std::array<double, N - 1>& query) {
  Matrix<N> m;
  for (int r = 0; r < N; ++r) {
    double sum = 0;
    for (int c = 0; c + 1 < N; ++c) m[r][c] = points[r][c] - query[c], sum += m[r][c] * m[r][c];
    m[r][N - 1] = sum;
  }
  return m;
}

template <int N>
void expect_never_wrong_on_nearly_singular(std::mt19937_64& random, int trials) {
  std::uniform_real_distribution<double> coordinate(-1, 1), exponent(-17, -10);
  std::uniform_int_distribution<int> which(0, N - 1);
  int decided = 0, undecided = 0;
  for (int trial = 0; trial < trials; ++trial) {
    // A row that is a combination of two others but for a perturbation
    // near the rounding: the sign is at the edge of what doubles can tell.
    Matrix<N> m;
    for (auto& row : m)
      for (double& x : row) x = coordinate(random);
    const int r = which(random), a = (r + 1) % N, b = (r + 2) % N;
    const double s = coordinate(random), t = coordinate(random);
    for (int c = 0; c < N; ++c) {
      const double perturbation = trial % 3 ? std::copysign(std::pow(10.0, exponent(random)), coordinate(random)) : 0.0;
      m[r][c] = s * m[a][c] + t * m[b][c] + perturbation;
    }
    const std::optional<int> sign = certain_sign<N>(m, Columns::Differences);
    if (sign) {
      ++decided;
      ASSERT_EQ(*sign, exact_sign<N>(m)) << "trial " << trial;
    } else {
      ++undecided;
    }
  }
  // Both kinds met: the test reaches the bound from both sides.
  EXPECT_GT(decided, 0);
  EXPECT_GT(undecided, 0);
}

TEST(CertainDeterminant, WhereItDecidesTheSignIsTheExactOneOnNearlySingularMatrices) {
  std::mt19937_64 random(7);
  expect_never_wrong_on_nearly_singular<3>(random, 3000);
  expect_never_wrong_on_nearly_singular<4>(random, 3000);
  expect_never_wrong_on_nearly_singular<5>(random, 3000);
}

TEST(CertainDeterminant, DecidesWellConditionedMatricesAndTheirSignIsExact) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> coordinate(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    Matrix<5> m;
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 5; ++c) m[r][c] = coordinate(random) + (r == c ? 4.0 : 0.0);  // diagonally dominant
    const std::optional<int> sign = certain_sign<5>(m, Columns::Differences);
    ASSERT_TRUE(sign.has_value()) << "trial " << trial;
    EXPECT_EQ(*sign, exact_sign<5>(m));
  }
}

TEST(CertainDeterminant, CosphericalPointsAreLeftToTheExactPredicateAndOthersDecided) {
  // The 16 corners of a 4D unit cube lie on one sphere: any 5 of them and
  // a sixth make a zero lifted determinant, which rounding must not sign.
  std::array<std::array<double, 4>, 16> corner;
  for (int k = 0; k < 16; ++k)
    for (int c = 0; c < 4; ++c) corner[k][c] = 0.1 + 0.3 * ((k >> c) & 1);  // 0.1 and 0.4: not exact in binary
  std::mt19937_64 random(3);
  std::uniform_int_distribution<int> pick(0, 15);
  int zeros = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    std::array<std::array<double, 4>, 5> cell;
    for (auto& p : cell) p = corner[pick(random)];
    const std::array<double, 4> query = corner[pick(random)];
    const Matrix<5> m = lifted<5>(cell, query);
    const int exact = exact_sign<5>(m);
    const std::optional<int> sign = certain_sign<5>(m, Columns::Lifted);
    if (sign) EXPECT_EQ(*sign, exact) << "trial " << trial;
    zeros += exact == 0;
  }
  EXPECT_GT(zeros, 1000);
}

TEST(CertainDeterminant, AColumnOfExactZerosIsACertainZero) {
  // Five points sharing their last coordinate (one layer of the fill).
  Matrix<4> m = {{{0.3, -0.2, 0.7, 0.0}, {0.1, 0.9, -0.4, 0.0}, {-0.8, 0.2, 0.5, 0.0}, {0.6, 0.6, 0.1, 0.0}}};
  EXPECT_EQ(certain_sign<4>(m, Columns::Differences), std::optional<int>(0));
}

TEST(CertainDeterminant, ALiftedColumnThatUnderflowedIsNotTakenForAZero) {
  // Differences of 1e-170: their squares underflow to zero, the exact
  // lifted determinant does not vanish.
  std::array<std::array<double, 2>, 3> points = {{{1e-170, 0}, {0, 1e-170}, {-1e-170, 0}}};
  const Matrix<3> m = lifted<3>(points, {0, -0.5e-170});
  for (int r = 0; r < 3; ++r) ASSERT_EQ(m[r][2], 0.0);
  EXPECT_FALSE(certain_sign<3>(m, Columns::Lifted).has_value());
}

TEST(CertainDeterminant, NonFiniteEntriesAreLeftUndecided) {
  Matrix<3> m = {{{1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}};
  EXPECT_FALSE(certain_sign<3>(m, Columns::Differences).has_value());
  m[2][2] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(certain_sign<3>(m, Columns::Differences).has_value());
}

}  // namespace
}  // namespace animanifold
