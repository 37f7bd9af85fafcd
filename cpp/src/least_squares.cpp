#include "least_squares.hpp"

#include <Eigen/QR>

namespace animanifold {

Eigen::VectorXd least_squares_solution(const Eigen::MatrixXd& M, const Eigen::VectorXd& b) {
  return Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(M).solve(b);
}

Eigen::VectorXd minimum_norm_solution(const Eigen::MatrixXd& M, const Eigen::VectorXd& b) {
  return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(M).solve(b);
}

}  // namespace animanifold
