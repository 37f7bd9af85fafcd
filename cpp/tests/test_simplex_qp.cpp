// The simplex-constrained quadratic programme (simplex_qp.hpp).
#include "animanifold/simplex_qp.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

using namespace animanifold;

TEST(SimplexQP, SatisfiesKKTOnRandomProblems) {
  std::mt19937 gen(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    const int k = 3 + trial % 20, D = 3 + trial % 2;
    Eigen::MatrixXd E(k, D);
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < D; ++j) E(i, j) = normal(gen);
    Eigen::MatrixXd H = 2 * E * E.transpose();
    H.diagonal().array() += 1e-6;
    const Eigen::VectorXd g = 0.3 * E.rowwise().squaredNorm();
    const double lower = 0.01;
    const SimplexQPResult r = solve_simplex_qp(H, g, lower);
    ASSERT_TRUE(r.converged) << "trial " << trial;
    EXPECT_NEAR(r.weights.sum(), 1.0, 1e-12);
    EXPECT_GE(r.weights.minCoeff(), lower - 1e-14);
    const Eigen::VectorXd gradient = H * r.weights + g;
    double nu = 0;
    int free = 0;
    for (int j = 0; j < k; ++j)
      if (r.weights(j) > lower + 1e-9) nu += gradient(j), ++free;
    ASSERT_GT(free, 0);
    nu /= free;
    for (int j = 0; j < k; ++j) {
      if (r.weights(j) > lower + 1e-9) EXPECT_NEAR(gradient(j), nu, 1e-7) << "trial " << trial;
      else EXPECT_GE(gradient(j), nu - 1e-7) << "trial " << trial;
    }
  }
}
