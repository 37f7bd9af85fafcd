// The sign of a small determinant in double precision, when rounding cannot
// have changed it: a semi-static filter in front of exact predicates.
//
// CGAL's dD kernel (Epick_d) filters its predicates with interval
// arithmetic only, the larger part of a 4D Delaunay triangulation's time
// (the field method's fill); its 2D and 3D kernels first try a floating-point
// evaluation with an error bound. certain_sign() is that first try for the
// dD predicates (semi_static_kernel_d.hpp): it says "not certain" where the
// bound does not rule out a wrong sign, and the exact predicate decides.
//
// The bound: the determinant is expanded by columns (each k x k minor of the
// first k columns from those of k - 1), one fixed tree of additions,
// subtractions and multiplications over the entries. For such a tree,
// evaluated in floating point, |computed - exact| <= gamma_h * A, where A is
// the same tree evaluated over the entries' absolute values with every
// subtraction an addition (here: the permanent of |m|, at most the product
// of its column sums), h the most roundings on a path from an entry to the
// root (the entries' own rounding included), and gamma_h = h u / (1 - h u)
// with u = 2^-53 (Higham, "Accuracy and Stability of Numerical Algorithms",
// 2nd ed., section 3.1).
//
// A column of exact zeros (entries that are differences of equal doubles:
// points sharing a coordinate, as the fill's layers do in time) makes the
// determinant exactly zero: that sign is certain too.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace animanifold {

// Roundings a matrix entry carries in: a difference of two doubles (1), or
// a sum of up to 4 squares of such differences (a lifted coordinate:
// 1 + 1 + 3 = 5).
inline constexpr int kDifferenceRoundings = 1;
inline constexpr int kLiftedRoundings = 5;

// What a matrix's columns hold: differences of two doubles (exactly zero
// only for equal ones), and, with `Lifted`, a last column of sums of their
// squares (which may underflow to zero).
enum class Columns { Differences, Lifted };

namespace certain_determinant_detail {

// One term of the expansion: minor[rows] += sign * m[row][column] * minor[rest].
struct Term {
  unsigned rows, rest;
  int row, column;
  double sign;
};

// The terms of every level (column 1 .. N-1), level by level: the row
// subsets of size column + 1 in ascending order, each row of a subset
// signed (-1)^(its position in the subset + column).
template <int N>
struct Expansion {
  static constexpr int kTerms = [] {
    int count = 0;
    for (unsigned rows = 0; rows < (1u << N); ++rows)
      if (__builtin_popcount(rows) >= 2) count += __builtin_popcount(rows);
    return count;
  }();
  std::array<Term, kTerms> terms{};
  constexpr Expansion() {
    int t = 0;
    for (int column = 1; column < N; ++column)
      for (unsigned rows = 0; rows < (1u << N); ++rows) {
        if (__builtin_popcount(rows) != column + 1) continue;
        int position = 0;
        for (int r = 0; r < N; ++r)
          if (rows & (1u << r))
            terms[t++] = {rows, rows & ~(1u << r), r, column, (position++ + column) % 2 ? -1.0 : 1.0};
      }
  }
};

}  // namespace certain_determinant_detail

// The sign (-1, 0 or 1) of the determinant of the N x N matrix `m` (rows),
// when the double-precision evaluation proves it; std::nullopt when the
// rounding error bound reaches the computed value, or the values leave the
// range where the bound holds (underflow, overflow, non-finite entries).
template <int N>
std::optional<int> certain_sign(const std::array<std::array<double, N>, N>& m, Columns columns) {
  static_assert(N >= 2 && N <= 6, "certain_sign() expands minors over row subsets: 2 <= N <= 6");
  const int differences = columns == Columns::Lifted ? N - 1 : N;
  double magnitude = 1;
  for (int c = 0; c < N; ++c) {
    double column_sum = 0;
    for (int r = 0; r < N; ++r) column_sum += std::abs(m[r][c]);
    if (column_sum == 0 && c < differences) return 0;
    magnitude *= column_sum;
  }
  static constexpr certain_determinant_detail::Expansion<N> kExpansion;
  std::array<double, (1u << N)> minor{};
  for (int r = 0; r < N; ++r) minor[1u << r] = m[r][0];
  // Unrolled, the table's entries are constants: straight-line code.
#pragma GCC unroll 256
  for (int t = 0; t < kExpansion.kTerms; ++t) {
    const certain_determinant_detail::Term& term = kExpansion.terms[t];
    minor[term.rows] += term.sign * (m[term.row][term.column] * minor[term.rest]);
  }
  const double value = minor[(1u << N) - 1];
  // Below this the products may have lost bits to underflow, which the
  // relative bound does not cover.
  constexpr double kSmallest = 1e-280;
  if (!std::isfinite(value) || !std::isfinite(magnitude) || !(magnitude > kSmallest)) return std::nullopt;
  // Each level: one multiplication and `column` additions on every path.
  int roundings = columns == Columns::Lifted ? kLiftedRoundings : kDifferenceRoundings;
  for (int column = 1; column < N; ++column) roundings += 1 + column;
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  const double gamma = roundings * u / (1 - roundings * u);
  // Twice the bound: a margin for the rounding of `magnitude` itself.
  if (std::abs(value) <= 2 * gamma * magnitude) return std::nullopt;
  return value > 0 ? 1 : -1;
}

}  // namespace animanifold
