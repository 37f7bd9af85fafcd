#pragma once
// Least-squares solutions of small dense systems, by rank-revealing QR
// decompositions (dependent columns get no wild coefficient). A unit of its
// own: the decompositions' templates are costly to compile, and a CI build
// compiles this unit once, uninstrumented (CMakeLists.txt).

#include <Eigen/Core>

namespace animanifold {

// Inputs:
//   M  rows by k (k small: a few columns)
//   b  rows
// Outputs:
//   k  the x minimising |M x - b|
Eigen::VectorXd least_squares_solution(const Eigen::MatrixXd& M, const Eigen::VectorXd& b);

// The same for an M that may be rank-deficient: of the x minimising
// |M x - b|, the shortest (complete orthogonal decomposition).
Eigen::VectorXd minimum_norm_solution(const Eigen::MatrixXd& M, const Eigen::VectorXd& b);

}  // namespace animanifold
