// Distances from points to a triangle mesh (R^3) or a polyline (R^2), for
// checking that a slice reproduces an input shape (§8.3, validity 2), and
// the closest points themselves, for carrying an input's UVs and materials
// onto a morph (animanifold/morph_surface.py).
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

// The closest point on a closed, consistently oriented triangle mesh to
// each of `points` (#P by 3), through CGAL's AABB tree.
//
// Outputs: its distance (unsigned), the face it lies on (the first such
// face the tree finds where several touch it: an edge or a corner), and its
// barycentric coordinates in that face's corners (#P by 3, summing to 1).
// Throws InputError naming the face when the mesh is not a manifold.
struct ClosestPoints {
  Eigen::VectorXd distance;
  IndexVector face;
  PointMatrix barycentric;
};
ClosestPoints closest_points(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
