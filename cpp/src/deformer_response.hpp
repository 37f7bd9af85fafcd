// Private: the Deformer's solution as an affine function of its handle
// transform. With anchors fixed and δ that of the rest shape, the handles'
// positions are H·T_topᵀ, where H = [V_h 1] holds the handles' homogeneous
// rest coordinates (#H by D+1) and T_top the first D rows of the (D+1) by
// (D+1) transform; the least-squares solution is linear in the constraint
// positions and the right-hand side, hence
//   X(T) = base + linear · T_topᵀ,
// with `base` the solution with every handle at the origin and column j of
// `linear` the solution for anchors at the origin, δ = 0 and the handles at
// column j of H. Once both are known (2D+1 solves with one factor), a deform
// by a transform is this dense combination instead of a sparse solve.
#pragma once

#include "animanifold/types.hpp"

#include <Eigen/Core>

namespace animanifold {

struct AffineResponse {
  PointMatrix base;    // #V by D
  PointMatrix linear;  // #V by D+1

  bool empty() const { return base.size() == 0; }
  // Inputs:
  //   transform  (D+1) by (D+1) affine map (checked by the caller)
  // Outputs:
  //   #V by D points base + linear · T_topᵀ, each entry summed in the same
  //   fixed order whatever the thread count (no threaded product: same bits).
  PointMatrix apply(const Eigen::MatrixXd& transform) const;
};

}  // namespace animanifold
