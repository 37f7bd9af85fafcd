#include "animanifold/simplex_qp.hpp"

#include "animanifold/errors.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

namespace animanifold {

SimplexQPResult solve_simplex_qp(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double lower,
                                 int max_iterations) {
  const int k = static_cast<int>(H.rows());
  if (k < 1) fail<InputError>("simplex QP needs at least one variable");
  if (H.cols() != k || g.size() != k)
    fail<InputError>("simplex QP: H is ", H.rows(), " by ", H.cols(), " and g has ", g.size(), " entries");
  if (!H.allFinite() || !g.allFinite() || !std::isfinite(lower))
    fail<InputError>("simplex QP: H, g and the lower bound must be finite");
  const double slack = 1.0 - k * lower;  // Σ u for u = w - lower >= 0
  if (slack < -1e-12)
    fail<InputError>("simplex QP: lower bound ", lower, " times ", k, " variables exceeds 1 (infeasible)");
  if (max_iterations <= 0) max_iterations = 20 * k + 20;

  SimplexQPResult result;
  result.weights = Eigen::VectorXd::Constant(k, lower);
  if (slack <= 0 || k == 1) {
    if (k == 1) result.weights(0) = 1.0;
    result.objective = 0.5 * result.weights.dot(H * result.weights) + g.dot(result.weights);
    result.converged = true;
    return result;
  }

  // Work in u = w - lower: gradient H u + g', g' = g + lower·H·1.
  const Eigen::VectorXd g_shift = g + lower * H.rowwise().sum();
  Eigen::VectorXd u = Eigen::VectorXd::Constant(k, slack / k);
  std::vector<char> active(k, 0);
  std::vector<int> free;
  free.reserve(k);
  Eigen::MatrixXd Hff(k, k);
  Eigen::VectorXd q(k), y(k), z(k), p(k);
  Eigen::LLT<Eigen::MatrixXd> llt(k);
  const double scale = std::max(H.diagonal().cwiseAbs().maxCoeff(), 1e-300);
  const double step_tol = 1e-14 * slack;
  bool on_subspace_minimum = false;  // the last step was a full (unblocked) one

  for (int it = 0; it < max_iterations; ++it) {
    result.iterations = it + 1;
    free.clear();
    for (int j = 0; j < k; ++j)
      if (!active[j]) free.push_back(j);
    const int m = static_cast<int>(free.size());
    const Eigen::VectorXd gradient = H * u + g_shift;
    for (int a = 0; a < m; ++a) {
      q(a) = gradient(free[a]);
      for (int b = 0; b < m; ++b) Hff(a, b) = H(free[a], free[b]);
    }
    llt.compute(Hff.topLeftCorner(m, m));
    if (llt.info() != Eigen::Success) fail<InputError>("simplex QP: H is not positive definite");
    y.head(m) = llt.solve(q.head(m));
    z.head(m) = llt.solve(Eigen::VectorXd::Ones(m));
    // Equality-constrained step on the free set: p = -H⁻¹(q + ν1) with 1ᵀp = 0.
    const double nu = -y.head(m).sum() / z.head(m).sum();
    p.head(m) = -(y.head(m) + nu * z.head(m));

    if (on_subspace_minimum || p.head(m).cwiseAbs().maxCoeff() <= step_tol) {
      on_subspace_minimum = false;
      // Stationary on the working set: check the bound multipliers μ_j = ∇_j + ν.
      int release = -1;
      double most_negative = -1e-12 * std::max(scale, gradient.cwiseAbs().maxCoeff());
      for (int j = 0; j < k; ++j)
        if (active[j] && gradient(j) + nu < most_negative) {
          most_negative = gradient(j) + nu;
          release = j;
        }
      if (release < 0) {
        result.converged = true;
        break;
      }
      active[release] = 0;
      continue;
    }
    double alpha = 1.0;
    int blocking = -1;
    for (int a = 0; a < m; ++a)
      if (p(a) < 0) {
        const double ratio = -u(free[a]) / p(a);
        if (ratio < alpha) {
          alpha = ratio;
          blocking = free[a];
        }
      }
    for (int a = 0; a < m; ++a) u(free[a]) += alpha * p(a);
    if (blocking >= 0) {
      u(blocking) = 0;
      active[blocking] = 1;
    } else {
      on_subspace_minimum = true;
    }
  }
  // Keep Σu exact despite rounding, then shift back.
  u = u.cwiseMax(0.0);
  const double total = u.sum();
  if (total > 0) u *= slack / total;
  result.weights = u.array() + lower;
  result.objective = 0.5 * result.weights.dot(H * result.weights) + g.dot(result.weights);
  return result;
}

}  // namespace animanifold
