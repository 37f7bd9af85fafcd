// Distances from points to a triangle mesh (R^3) or a polyline (R^2), for
// checking that a slice reproduces an input shape (§8.3, validity 2), and
// the closest points themselves, for carrying an input's UVs and materials
// onto a morph (animanifold/morph_surface.py).
#pragma once

#include "animanifold/types.hpp"

#include <memory>

namespace animanifold {

// Inputs:
//   points    #P by d
//   vertices  #V by d
//   faces     #F by d (triangles in R^3, segments in R^2)
// Outputs:
//   the largest point-to-surface distance (+infinity for an empty surface)
// Throws: InputError when the dimensions disagree or are not 2 or 3
//
// Largest distance from any of `points` (#P by d) to the surface made of
// `faces` (#F by d: triangles in R^3, segments in R^2) over `vertices`.
// Returns +infinity when the surface is empty and there are points.
double max_distance_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

// The distances to one triangle mesh in R^3, its search tree built once for
// many queries (distances_to_surface builds one per call).
// Inputs: vertices #V by 3, faces #F by 3 (degenerate faces are left out)
// Throws: InputError when the dimensions are not 3 or a face refers to a
//   vertex outside `vertices`
class TriangleDistance {
 public:
  TriangleDistance(const PointMatrix& vertices, const SimplexMatrix& faces);
  ~TriangleDistance();
  TriangleDistance(TriangleDistance&&) noexcept;
  TriangleDistance& operator=(TriangleDistance&&) noexcept;
  // The distance from each of `points` (#P by 3) to the mesh; +infinity
  // for all when it has no proper face.
  Eigen::VectorXd operator()(const PointMatrix& points) const;
  // The largest of those distances, operator()(points).maxCoeff(), but
  // faster: a point with a face within the largest found so far is passed
  // over without its distance. The same value to the bit unless that
  // largest distance is below about 1e-5 of the coordinates' magnitude
  // (then within rounding of it). 0 for no points.
  double farthest(const PointMatrix& points) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// Inputs: as max_distance_to_surface
// Outputs:
//   #P distances
// Throws: InputError when the dimensions disagree or are not 2 or 3, or a
//   face refers to a vertex outside `vertices`
//
// The distance from each of `points` to the surface (+infinity for all when
// the surface has no proper face).
Eigen::VectorXd distances_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

// closest_points:
// Inputs:
//   points    #P by 3
//   vertices  #V by 3
//   faces     #F by 3, a closed, consistently oriented triangle mesh
// Outputs:
//   ClosestPoints: per point its unsigned distance, the face its closest
//   point lies on, and that point's barycentric coordinates (#P by 3)
// Throws: InputError naming the face when the mesh is not a manifold
//
// The closest point on the mesh to each of `points`, through CGAL's AABB
// tree. Where several faces touch it (an edge or a corner), the face is the
// first the tree finds; the barycentric coordinates sum to 1.
struct ClosestPoints {
  Eigen::VectorXd distance;
  IndexVector face;
  PointMatrix barycentric;
};
ClosestPoints closest_points(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces);

}  // namespace animanifold
