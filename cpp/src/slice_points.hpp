// Internal to slicing (slice.cpp, interval_index.cpp, interval_frame.cpp):
// the snap tolerance and how a slice's points follow from their manifold
// edges. A fresh slice and a slice moved within its topology interval
// (Slicer::slice_in_interval) compute their points here, with the same
// arithmetic, so the two are identical bit for bit.
#pragma once

#include "animanifold/slice.hpp"

#include <cstdint>

namespace animanifold::slice_points {

// Values this share of the manifold's extent along the axis away from a
// vertex's coordinate slice at the vertex's (see slice()).
constexpr double kSnapToVertices = 1e-12;

// How close to a vertex coordinate a value is taken as it: kSnapToVertices of
// the manifold's extent along the axis. Scaled before subtracting, so that a
// manifold from -1e308 to 1e308 has a finite tolerance, not an infinite one.
inline double snap_tolerance(double lowest, double highest) {
  return kSnapToVertices * highest - kSnapToVertices * lowest;
}

// Where the plane {x_axis = value} crosses edge (a, b), a < b, as a share of
// the way from a to b (in (0, 1) for an edge it crosses strictly inside).
inline double edge_parameter(const PointMatrix& V, int axis, double value, Index a, Index b) {
  const double xa = V(a, axis), xb = V(b, axis);
  return (value - xa) / (xb - xa);
}

// Inputs:
//   m      the manifold sliced
//   axis   the axis it was sliced along
//   out    with vertex_edges (P by 2) and edge_parameter (P) set
// Outputs:
//   out.vertices: the coordinates other than `axis` of each point on its edge
//   (copied for a manifold vertex, a == b, so keyframes come back exactly);
//   out.vertex_attributes: every vertex attribute interpolated the same way,
//   unless with_attributes is false (a frame's shape only: slice_shape())
void interpolate_points(const Complex& m, int axis, Slice& out, bool with_attributes = true);

}  // namespace animanifold::slice_points
