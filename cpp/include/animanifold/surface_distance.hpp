// Distances from points to a triangle mesh (R^3) or a polyline (R^2), for
// checking that a slice reproduces an input shape (§8.3, validity 2).
#pragma once

#include "animanifold/types.hpp"

namespace animanifold {

// Largest distance from any of `points` (#P by d) to the surface made of
// `faces` (#F by d: triangles in R^3, segments in R^2) over `vertices`.
// Returns +infinity when the surface is empty and there are points.
double max_distance_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

// The distance from each of `points` to the surface (+infinity for all when
// the surface has no proper face).
Eigen::VectorXd distances_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
