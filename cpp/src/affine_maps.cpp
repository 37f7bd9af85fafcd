#include "animanifold/affine_maps.hpp"

#include "animanifold/errors.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <complex>

namespace animanifold {

void check_affine_transform(const Eigen::MatrixXd& transform, int dim) {
  if (transform.rows() != dim + 1 || transform.cols() != dim + 1)
    fail<InputError>("the handle transform must be ", dim + 1, " by ", dim + 1, " (affine, homogeneous) for ", dim,
                     "D points, got ", transform.rows(), " by ", transform.cols());
  if (!transform.allFinite()) fail<InputError>("the handle transform has non-finite entries");
  Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(dim + 1);
  expected(dim) = 1;
  if ((transform.row(dim) - expected).cwiseAbs().maxCoeff() > 1e-12)
    fail<InputError>("the handle transform's last row must be [0 ... 0 1] (an affine map)");
}

Eigen::MatrixXd affine_power(const Eigen::MatrixXd& transform, double s) {
  const int dim = static_cast<int>(transform.rows()) - 1;
  check_affine_transform(transform, dim);
  const Eigen::MatrixXd A = transform.topLeftCorner(dim, dim);
  const Eigen::VectorXd t = transform.topRightCorner(dim, 1);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::MatrixXd R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) fail<InputError>("the handle transform reflects: it cannot be applied in steps");
  const Eigen::VectorXd sigma = svd.singularValues();
  if (sigma.minCoeff() <= 0) fail<InputError>("the handle transform is singular: it cannot be applied in steps");
  const Eigen::MatrixXd S_s = svd.matrixV() * sigma.array().pow(s).matrix().asDiagonal() * svd.matrixV().transpose();
  // R is orthogonal, hence diagonalisable: R^s = U Λ^s U⁻¹.
  const Eigen::ComplexEigenSolver<Eigen::MatrixXd> eigen(R);
  const Eigen::MatrixXcd U = eigen.eigenvectors();
  Eigen::VectorXcd lambda = eigen.eigenvalues();
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    const double angle = std::arg(lambda(i));
    if (std::abs(std::abs(angle) - M_PI) < 1e-9 && s != 0 && s != 1)
      fail<InputError>("the handle transform rotates by π: its increments are ambiguous; apply it as two halves");
    lambda(i) = std::polar(1.0, angle * s);
  }
  const Eigen::MatrixXcd R_c = U * lambda.asDiagonal() * U.inverse();
  if (R_c.imag().cwiseAbs().maxCoeff() > 1e-8)
    fail<InputError>("the handle transform's rotation has no real fractional power");
  const Eigen::MatrixXd A_s = R_c.real() * S_s;
  const Eigen::MatrixXd IA = Eigen::MatrixXd::Identity(dim, dim) - A;
  const Eigen::VectorXd c = IA.completeOrthogonalDecomposition().solve(t);
  const Eigen::VectorXd r = t - IA * c;
  Eigen::MatrixXd out = Eigen::MatrixXd::Identity(dim + 1, dim + 1);
  out.topLeftCorner(dim, dim) = A_s;
  out.topRightCorner(dim, 1) = c - A_s * c + s * r;
  return out;
}

Eigen::MatrixXd best_fit_rigid(const PointMatrix& rest, const PointMatrix& moved) {
  const int dim = static_cast<int>(rest.cols());
  const Eigen::RowVectorXd a0 = rest.colwise().mean(), b0 = moved.colwise().mean();
  const Eigen::MatrixXd cross = (moved.rowwise() - b0).transpose() * (rest.rowwise() - a0);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::MatrixXd U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(dim - 1) *= -1;
  const Eigen::MatrixXd R = U * svd.matrixV().transpose();
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(dim + 1, dim + 1);
  T.topLeftCorner(dim, dim) = R;
  T.topRightCorner(dim, 1) = (b0 - a0 * R.transpose()).transpose();
  return T;
}

}  // namespace animanifold
