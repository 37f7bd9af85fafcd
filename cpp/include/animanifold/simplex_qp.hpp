// A small dedicated solver for the per-vertex quadratic programs of the
// graph Laplacian (eq. 4.2 and its boundary form 4.3, chapter 4).
//
// Every vertex asks for weights on its one-ring (tens of variables) that sum
// to one and stay above a floor ξ. These are tiny strictly convex QPs over a
// shifted simplex; a primal active-set method with a dense Cholesky of the
// free block solves one in a handful of iterations (microseconds), where a
// general-purpose QP solver's set-up alone costs far more than the solve.
#pragma once

#include <Eigen/Core>

namespace animanifold {

struct SimplexQPResult {
  Eigen::VectorXd weights;  // k weights, sum 1, each >= lower
  double objective = 0;     // ½ wᵀHw + gᵀw at `weights`
  int iterations = 0;       // active-set iterations used
  bool converged = false;   // the KKT conditions hold to working precision
};

// Inputs:
//   H               k by k symmetric positive definite
//   g               k
//   lower           the floor of every weight (k * lower <= 1)
//   max_iterations  0: 20·k + 20
// Outputs:
//   SimplexQPResult: weights (k), objective, iterations, converged
// Throws: InputError (see below)
//
// min_w ½ wᵀ H w + gᵀ w  such that  Σ w_j = 1  and  w_j >= lower for all j.
//
// H (k by k) must be symmetric positive definite (the graph Laplacian adds a
// tiny ridge to its rank-deficient Gram matrix for that); g has k entries;
// k * lower must not exceed 1. Throws InputError on wrong sizes, non-finite
// input, an infeasible floor, or an H that is not positive definite.
// Primal active-set method (Nocedal & Wright, Algorithm 16.3) started from the
// uniform weights, which are feasible; at most `max_iterations` steps
// (default 20·k + 20), reporting converged = false if that cap is reached.
SimplexQPResult solve_simplex_qp(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double lower,
                                 int max_iterations = 0);

}  // namespace animanifold
