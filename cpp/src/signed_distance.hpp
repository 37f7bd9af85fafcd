// Signed distance to a closed, outward-oriented triangle mesh in R^3, with
// the closest point (the field morph's distance fields, morph_field.hpp).
//
// Inputs: the mesh (#V by 3 points, #F by 3 triangles), closed and
// consistently oriented (the morph checks its inputs first). Outputs, for
// each query point: the distance to the surface, negative inside; the face
// the closest point lies on; its barycentric coordinates there. Throws:
// InputError when a vertex or a query point is not finite or lies beyond
// kMaxDerivedCoordinate (coordinate_bound.hpp), whose powers CGAL cannot take.
//
// The magnitude is CGAL's AABB-tree closest point; the side is CGAL's
// Side_of_triangle_mesh (ray shooting through the same tree), which is exact
// about which side a point lies on where the closest point is ambiguous (a
// query near an edge of a thin fold), unlike the sign of the closest face's
// normal. A point on the surface is "inside" for the side test; its distance
// is zero to rounding either way.
#pragma once

#include "animanifold/surface_distance.hpp"
#include "animanifold/types.hpp"

#include <memory>

namespace animanifold {

// The closest points with the distance signed: negative inside.
using SurfaceProjection = ClosestPoints;

class SignedDistance {
 public:
  SignedDistance(const PointMatrix& vertices, const SimplexMatrix& faces);
  ~SignedDistance();
  SignedDistance(SignedDistance&&) noexcept;
  SignedDistance& operator=(SignedDistance&&) noexcept;

  // `points` is #P by 3.
  SurfaceProjection operator()(const PointMatrix& points) const;
  // The closest points alone: unsigned distances, no side test.
  ClosestPoints closest(const PointMatrix& points) const;
  // The signed distances alone.
  Eigen::VectorXd distances(const PointMatrix& points) const;
  // The side alone: whether each point lies inside the surface or on it
  // (inside a cavity or a tunnel is outside). No distance is computed.
  Eigen::Array<bool, Eigen::Dynamic, 1> inside(const PointMatrix& points) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace animanifold
