// Normals of n-simplices in R^(n+1) by the generalised cross (wedge) product
// of eq. 2.2, area-weighted smooth vertex normals (eq. 2.3) and dropping a
// component to get lower-dimensional normals (§2.3.2).
#pragma once

#include "animanifold/types.hpp"

namespace animanifold {

// Inputs:
//   vectors  n by n+1
// Outputs:
//   the n+1 vector orthogonal to them, of length their parallelotope's n-volume
// Throws: InputError when vectors is not n by n+1
//
// Wedge product of n vectors in R^(n+1) (rows of `vectors`, n by n+1), with
// the unit vectors on the bottom row of the determinant as in eq. 2.2. Its
// length is the n-volume of the parallelotope the vectors span. In R^3 it is
// the cross product.
Eigen::VectorXd wedge(const PointMatrix& vectors);

// Inputs:
//   V  #V by D points
//   S  #S by D simplices (n-simplices in R^(n+1))
// Outputs:
//   #S by D normals, of length n! times the simplex's n-volume
// Throws: InputError when S.cols() != V.cols() or an index is outside V (check_indices)
//
// Unnormalised normal of every simplex: wedge(v1-v0, ..., vn-v0). Its length
// is n! times the simplex's n-volume, so summing these is area weighting.
// Requires S.cols() == V.cols() (n-simplices in R^(n+1)). #S by D.
PointMatrix simplex_normals(const PointMatrix& V, const SimplexMatrix& S);

// Inputs:
//   V  #V by D points
//   S  #S by D simplices
// Outputs:
//   #V by D unit normals (zero rows where undefined)
// Throws: InputError when S.cols() != V.cols() or an index is outside V (check_indices)
//
// Area-weighted smooth vertex normals (eq. 2.3), unit length; zero for a
// vertex with no incident simplex or whose incident normals cancel. #V by D.
PointMatrix vertex_normals(const PointMatrix& V, const SimplexMatrix& S);

// Inputs:
//   normals  #N by D
//   axis     0..D-1
// Outputs:
//   #N by D-1 unit normals (zero rows stay zero)
// Throws: InputError when axis is out of range
//
// Drops column `axis` of the normals and renormalises each row (§2.3.2):
// the normal in R^(D-1) of the iso-slice perpendicular to that axis. Rows
// that become zero stay zero.
PointMatrix drop_component(const PointMatrix& normals, int axis);

// Inputs:
//   vertices  #P by d (d = 3 or 2)
//   faces     #F by d (triangles, or segments)
// Outputs:
//   #P by d unit vertex normals
// Throws: InputError unless d is 2 or 3 and faces have d corners, or for an
//   index outside vertices (check_indices)
//
// Area-weighted unit vertex normals of a frame: triangles in R^3 (right-hand
// rule) or segments in R^2 (the right side of each segment, outward for a
// counter-clockwise polygon). A frame face lies in the hyperplane of the
// manifold simplex it was cut from, so its normal is that simplex's wedge
// normal with the slicing axis dropped (§2.3.2); averaging over the frame's
// own faces keeps normals smooth across the frame without blending in the
// shape at other times. #P by d; zero for an unused vertex.
PointMatrix frame_vertex_normals(const PointMatrix& vertices, const SimplexMatrix& faces);
// As frame_vertex_normals(), without check_indices: for faces whose indices
// are in range by construction (a slice's own, from its cut).
PointMatrix frame_vertex_normals_unchecked(const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
