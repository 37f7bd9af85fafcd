#include "deformer_response.hpp"

namespace animanifold {

PointMatrix AffineResponse::apply(const Eigen::MatrixXd& transform) const {
  const Eigen::Index rows = base.rows(), dim = base.cols(), terms = linear.cols();
  PointMatrix out(rows, dim);
  for (Eigen::Index v = 0; v < rows; ++v)
    for (Eigen::Index c = 0; c < dim; ++c) {
      double sum = base(v, c);
      for (Eigen::Index j = 0; j < terms; ++j) sum += linear(v, j) * transform(c, j);
      out(v, c) = sum;
    }
  return out;
}

}  // namespace animanifold
