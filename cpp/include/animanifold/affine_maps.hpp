#pragma once
// Affine maps of a deformation's handles (laplacian.hpp's Deformer): checking
// that a matrix is one, its fractional powers (the increments of a deformation
// in steps), and the rigid motion best fitting moved points.
//
// Their dense decompositions (SVD, complex eigenvectors) are most of what
// compiling the Deformer costs, so they live in a unit of their own, which a
// CI build compiles once, uninstrumented (CMakeLists.txt).

#include "animanifold/types.hpp"

#include <Eigen/Core>

namespace animanifold {

// Inputs:
//   transform  a matrix meant as the (dim+1) by (dim+1) homogeneous affine map
//              of dim-D points
// Throws: InputError naming what is wrong: the size, a non-finite entry, a
//   last row other than [0 ... 0 1]
void check_affine_transform(const Eigen::MatrixXd& transform, int dim);

// Inputs:
//   transform  (D+1) by (D+1) affine map T
//   s          in [0, 1]
// Outputs:
//   (D+1) by (D+1) T^s
// Throws: InputError for reflections and rotations by exactly π
//
// The affine map T^s for s in [0, 1] (T is (D+1) by (D+1) affine): polar
// factors R^s S^s about T's least-squares fixed point c, plus s times the
// translation left along the rotation axis: x ↦ R^s S^s (x − c) + c + s·r.
// T^0 = I, T^1 = T. InputError for reflections and rotations by exactly π.
Eigen::MatrixXd affine_power(const Eigen::MatrixXd& transform, double s);

// Inputs:
//   rest, moved  #P by D points, row p of `moved` where row p of `rest` went
// Outputs:
//   (D+1) by (D+1) the rigid motion (Kabsch: rotation and translation, no
//   reflection) that best maps the rows of `rest` onto those of `moved`
Eigen::MatrixXd best_fit_rigid(const PointMatrix& rest, const PointMatrix& moved);

}  // namespace animanifold
