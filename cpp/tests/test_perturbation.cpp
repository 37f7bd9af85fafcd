#include "animanifold/perturbation.hpp"

#include <gtest/gtest.h>

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
