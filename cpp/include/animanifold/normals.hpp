// Normals of n-simplices in R^(n+1) by the generalised cross (wedge) product
// of eq. 2.2, area-weighted smooth vertex normals (eq. 2.3) and dropping a
// component to get lower-dimensional normals (§2.3.2).
#pragma once

#include "animanifold/types.hpp"

namespace animanifold {

// Wedge product of n vectors in R^(n+1) (rows of `vectors`, n by n+1), with
// the unit vectors on the bottom row of the determinant as in eq. 2.2. Its
// length is the n-volume of the parallelotope the vectors span. In R^3 it is
// the cross product.
Eigen::VectorXd wedge(const PointMatrix& vectors);

// Unnormalised normal of every simplex: wedge(v1-v0, ..., vn-v0). Its length
// is n! times the simplex's n-volume, so summing these is area weighting.
// Requires S.cols() == V.cols() (n-simplices in R^(n+1)). #S by D.
PointMatrix simplex_normals(const PointMatrix& V, const SimplexMatrix& S);

// Area-weighted smooth vertex normals (eq. 2.3), unit length; zero for a
// vertex with no incident simplex or whose incident normals cancel. #V by D.
PointMatrix vertex_normals(const PointMatrix& V, const SimplexMatrix& S);

// Drops column `axis` of the normals and renormalises each row (§2.3.2):
// the normal in R^(D-1) of the iso-slice perpendicular to that axis. Rows
// that become zero stay zero.
PointMatrix drop_component(const PointMatrix& normals, int axis);

// Area-weighted unit vertex normals of a frame: triangles in R^3 (right-hand
// rule) or segments in R^2 (the right side of each segment, outward for a
// counter-clockwise polygon). A frame face lies in the hyperplane of the
// manifold simplex it was cut from, so its normal is that simplex's wedge
// normal with the slicing axis dropped (§2.3.2); averaging over the frame's
// own faces keeps normals smooth across the frame without blending in the
// shape at other times. #P by d; zero for an unused vertex.
PointMatrix frame_vertex_normals(const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
