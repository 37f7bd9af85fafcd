// Iso-slices of an animation manifold along any axis (§2.6, Figure 2.6).
//
// A frame at time t is the intersection of the manifold (n-simplices in
// R^(n+1)) with the hyperplane {x_axis = t}, an (n-1)-manifold in R^n:
// triangles in R^3 for tets in R^4, segments in R^2 for triangles in R^3.
// Slicing along x, y or z instead of t gives the sweep views of Figure 2.7.
//
// The output is welded: a cut through a manifold vertex is keyed by that
// vertex and a cut through an edge by the edge, so a closed manifold gives a
// watertight slice. Vertices lying exactly on the hyperplane count as below
// it (as if the plane were lifted by an infinitesimal), except at the top
// end of the manifold where they count as above, so a slice at any keyframe
// time (the first and last included) returns that keyframe exactly: same
// vertex positions (copied, not interpolated), same faces, same orientation.
// Faces that collapse (a repeated vertex key) are removed.
//
// Orientation: each slice face is the facet, lying on the hyperplane, of the
// part of its simplex above the cut, oriented outward by the facet rule of
// §2.4; this is the table of Figure 2.6. Slices along t keep the keyframes'
// orientation; slices along another axis are turned where needed so their
// faces agree with their (outward) normals.
#pragma once

#include "animanifold/complex.hpp"

#include <memory>
#include <vector>

namespace animanifold {

// The frame extracted by a slice.
struct Slice {
  PointMatrix vertices;   // P by D-1: the coordinates other than `axis`, in order
  SimplexMatrix faces;    // F by n: triangles (tets in R^4) or segments (triangles in R^3)
  PointMatrix normals;    // P by D-1: smooth unit normals (frame_vertex_normals: the cut simplices' own)
  VertexAttributes vertex_attributes;  // interpolated along the cut edges
  SimplexAttributes face_attributes;   // carried from the cut simplex
  // P by 2: the manifold edge (a, b), a < b, each slice vertex lies on; a == b
  // when it is a manifold vertex. `edge_parameter` (P) is its position from a to b.
  SimplexMatrix vertex_edges;
  Eigen::VectorXd edge_parameter;
  IndexVector face_simplex;  // F: the manifold simplex each face was cut from
};

// Inputs (constructor):
//   V     #V by D points
//   S     #S by k simplices
//   axis  0..D-1
// Outputs: stab(value) appends the simplices whose extent holds value
// Throws: InputError when axis is out of range
//
// An interval index over the simplices' extents along one axis: a sorted
// array of [min, max] intervals augmented with subtree maxima (an implicit
// interval tree), so a stabbing query costs O(log #S + hits), not O(#S).
class IntervalIndex {
 public:
  IntervalIndex(const PointMatrix& V, const SimplexMatrix& S, int axis);
  // Appends the simplices whose extent along the axis contains `value`.
  void stab(double value, std::vector<Index>& out) const;
  int axis() const { return axis_; }
  double lowest() const { return lowest_; }
  double highest() const { return highest_; }
  size_t memory_bytes() const;

 private:
  struct Node {
    double low, high, subtree_high;
    Index simplex;
  };
  std::vector<Node> nodes_;  // sorted by low; implicit tree over indices
  int levels_ = 0;
  int axis_;
  double lowest_, highest_;
};

// Inputs:
//   manifold  n-simplices in R^(n+1) (#S by D over #V by D points)
//   axis      0..D-1 (D-1 is time)
//   value     where to cut
//   index     optional IntervalIndex built on the same manifold and axis
// Outputs:
//   Slice: vertices P by D-1, faces F by n, normals, interpolated attributes,
//   each vertex's manifold edge and parameter, each face's simplex
// Throws: InputError for other simplices than tets in R^4 or triangles in R^3, an axis
//   out of range, a value that is not finite, or an index built on another axis
//
// Slices `manifold` at `value` along `axis` (0..D-1; D-1 is time).
// `index`, when given, must have been built on the same manifold and axis;
// without it every simplex is tested.
//
// Normals: each frame face lies in the hyperplane of the simplex it was cut
// from, so the simplex's wedge normal with the axis dropped (§2.3.2) is the
// face's normal; vertex normals average them over the frame's faces,
// weighted by area (frame_vertex_normals). Averaging the manifold's vertex
// normals instead would blend in the tets of neighbouring time slabs, which
// tilts frame normals wherever the shape changes quickly.
Slice slice(const Complex& manifold, int axis, double value, const IntervalIndex* index = nullptr);

}  // namespace animanifold

namespace animanifold {

// Keeps a manifold with what repeated slicing needs: one interval index per
// axis, each built on first use. Slicing the same manifold for every frame
// of a timeline then costs what each frame cuts.
class Slicer {
 public:
  explicit Slicer(std::shared_ptr<const Complex> manifold);
  Slice slice(int axis, double value, bool use_index = true);
  const IntervalIndex& index(int axis);
  const Complex& manifold() const { return *manifold_; }

 private:
  std::shared_ptr<const Complex> manifold_;
  std::vector<std::unique_ptr<IntervalIndex>> indices_;
};

}  // namespace animanifold
