// Position-keyed perturbation and the report of failed perturbations
// (perturbation.hpp).
#include "animanifold/perturbation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace animanifold;

TEST(FailedPerturbations, NamesEveryFailureOnceWithThePerturbationsItHappenedAt) {
  // The fan-capped cylinder -> torus: TetGen runs out of time twice, then
  // fails otherwise; the report must name every failure, not only the last.
  const std::string slow = "the source: TetGen ... (it did not finish within 13 s and was stopped)";
  const std::string moved = "the source: TetGen moved input point 6865";
  EXPECT_EQ(failed_perturbations({{1e-7, slow}, {1e-6, slow}, {1e-5, moved}}),
            slow + " with the inputs perturbed by 1e-07 and 1e-06 of their size; then " + moved + " at 1e-05");
  EXPECT_EQ(failed_perturbations({{1e-7, moved}, {1e-6, slow}, {1e-5, moved}}),
            moved + " with the inputs perturbed by 1e-07 of their size; then " + slow + " at 1e-06; then " + moved +
                " at 1e-05");
  EXPECT_EQ(failed_perturbations({{1e-7, slow}, {1e-6, slow}, {1e-5, slow}}),
            slow + " with the inputs perturbed by 1e-07, 1e-06 and 1e-05 of their size");
  EXPECT_EQ(failed_perturbations({}), "");
}

TEST(Perturbation, IsAFunctionOfPositionOnly) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  PointMatrix V(50, 3);
  for (Index r = 0; r < V.rows(); ++r) V.row(r) << g(rng), g(rng), g(rng);
  V.row(7) << 0.0, -0.0, 1.0;
  PointMatrix reversed = V.colwise().reverse();
  reversed.row(V.rows() - 1 - 7) << -0.0, 0.0, 1.0;  // -0.0 and 0.0 alike
  const PointMatrix a = perturbed_by_position(V, 1e-3, 42), b = perturbed_by_position(reversed, 1e-3, 42);
  for (Index r = 0; r < V.rows(); ++r) EXPECT_EQ(a.row(r), b.row(V.rows() - 1 - r)) << r;
  double largest = 0.0, mean = 0.0;
  for (Index r = 0; r < V.rows(); ++r)
    for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(a(r, c) - V(r, c))), mean += (a(r, c) - V(r, c));
  EXPECT_LE(largest, 1e-3);
  EXPECT_GT(largest, 5e-4);                 // spread over the range, not stuck near 0
  EXPECT_LT(std::abs(mean / 150), 2e-4);    // and centred
  EXPECT_NE(perturbed_by_position(V, 1e-3, 43), a);  // another salt, other offsets
  // Coordinates of one point get different offsets.
  EXPECT_NE(position_hash_offset(V.row(3).data(), 3, 0, 42), position_hash_offset(V.row(3).data(), 3, 1, 42));
}
