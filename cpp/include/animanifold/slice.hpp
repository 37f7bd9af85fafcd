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
#include <mutex>
#include <optional>
#include <utility>
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
// Outputs: stab(V, S, value) appends the simplices whose extent holds value
// Throws: InputError when axis is out of range (S's indices are not checked:
//   build it on a validated complex, Complex::validate); the methods below say
//   what each throws
//
// An interval index over the simplices' extents along one axis: a sorted
// array of [min, max] intervals augmented with subtree maxima (an implicit
// interval tree), so a stabbing query costs O(log #S + hits), not O(#S).
// Memory: 12 bytes a simplex plus 8 a distinct vertex coordinate. The
// tree keeps its bounds in single precision, rounded outward, and the
// simplex's own points decide each hit exactly, so hits are exact.
class IntervalIndex {
 public:
  IntervalIndex(const PointMatrix& V, const SimplexMatrix& S, int axis);

  // Inputs:
  //   V, S   the points and simplices the index was built on
  //   value  where to stab
  //   out    hits are appended to it
  // Outputs: out with the simplices whose extent along the axis contains `value`
  //   appended, in the index's order: by lowest coordinate along the axis, then by simplex
  // Throws: InputError when V or S do not have the counts the index was built on
  void stab(const PointMatrix& V, const SimplexMatrix& S, double value, std::vector<Index>& out) const;
  // Inputs:
  //   value  where to stab
  //   out    candidates are appended to it
  // Outputs: out with stab()'s hits appended, in the order stab() would, and possibly
  //   simplices whose extent misses `value` by less than a float's rounding
  // Throws: nothing
  //
  // For callers that read the simplices' points anyway (slicing skips
  // simplices on one side).
  void stab_candidates(double value, std::vector<Index>& out) const;
  // Inputs:
  //   value  a coordinate along the axis
  // Outputs: the topology interval around `value`: the open interval (lo, hi)
  //   between the nearest vertex coordinates below and above it; nullopt when
  //   `value` lies on a vertex coordinate (or within the rounding slice() snaps
  //   to one) or outside (lowest, highest), where the faces change
  // Throws: nothing
  //
  // No vertex lies inside the interval, so every slice there cuts the same
  // edges into the same faces.
  std::optional<std::pair<double, double>> topology_interval(double value) const;
  // Inputs:
  //   value      a coordinate along the axis
  //   tolerance  >= 0
  // Outputs: whether some vertex's coordinate along the axis lies within
  //   `tolerance` of `value`
  // Throws: nothing
  bool has_vertex_value_near(double value, double tolerance) const;

  // Outputs: the axis; the lowest and highest coordinate of the simplices along it
  //   (+inf and -inf without simplices); the index's memory in bytes
  // Throws: nothing
  int axis() const { return axis_; }
  double lowest() const { return lowest_; }
  double highest() const { return highest_; }
  size_t memory_bytes() const;

 private:
  struct Node {
    float low;           // the simplex's lowest coordinate, rounded down
    float subtree_high;  // the highest coordinate in the node's subtree, rounded up
    Index simplex;
  };
  std::vector<Node> nodes_;  // sorted by exact low, then simplex; implicit tree over indices
  std::vector<double> vertex_values_;  // the distinct vertex coordinates along the axis, sorted
  Index vertex_count_;
  int axis_;
  double lowest_, highest_;

  // stab_candidates() over the nodes [lo, hi), a subtree of the implicit tree.
  void stab_range(size_t lo, size_t hi, double value, std::vector<Index>& out) const;
  // The same walk over [lo, hi), cut into pieces for threads (interval_index.cpp).
  struct StabPiece;
  void plan_stab(size_t lo, size_t hi, double value, std::vector<StabPiece>& pieces) const;
};

// Seconds the stages of one slice took: the benchmark's breakdown.
struct SliceStages {
  double stab = 0;     // finding the simplices the plane may cut, and snapping to vertices
  double cut = 0;      // cutting them, each chunk listing its points once
  double weld = 0;     // numbering the chunks' points, one per manifold edge or vertex, and the faces' corners
  double output = 0;   // the frame's points, attributes and faces
  double normals = 0;  // its vertex normals
};

// Inputs:
//   manifold  n-simplices in R^(n+1) (#S by D over #V by D points)
//   axis      0..D-1 (D-1 is time)
//   value     where to cut
//   index     optional IntervalIndex built on the same manifold and axis
//   stages    optional: receives the seconds each stage took
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
// Threads: the cut runs on OpenMP's threads in chunks of a fixed size; the
// weld shares the points between the threads and numbers them in the order
// the chunks, taken in order, first meet them; each thread sums the normals
// of its own vertices in face order. The output (its order included) is the
// same for any thread count.
//
// Normals: each frame face lies in the hyperplane of the simplex it was cut
// from, so the simplex's wedge normal with the axis dropped (§2.3.2) is the
// face's normal; vertex normals average them over the frame's faces,
// weighted by area (frame_vertex_normals). Averaging the manifold's vertex
// normals instead would blend in the tets of neighbouring time slabs, which
// tilts frame normals wherever the shape changes quickly.
Slice slice(const Complex& manifold, int axis, double value, const IntervalIndex* index = nullptr,
            SliceStages* stages = nullptr);

// Inputs: as slice() (without stages)
// Outputs: slice()'s vertices, faces, vertex_edges, edge_parameter and
//   face_simplex, bit for bit; no normals, no vertex or face attributes
// Throws: as slice()
//
// A frame's shape only: what checks of its topology or crossings read,
// without the cost of the normals and the attributes no check looks at.
Slice slice_shape(const Complex& manifold, int axis, double value, const IntervalIndex* index = nullptr);

}  // namespace animanifold

namespace animanifold {

// A frame with how it moves inside its topology interval: live playback.
// Made by Slicer::interval_frame; a plain value (nothing of it throws).
//
// Inputs (of the frame as a function of v):
//   v  any value in the open interval (lo, hi)
// Outputs:
//   the slice at v: the faces, vertex_edges, face attributes and face_simplex
//   of `slice`, and, each vertex sliding linearly along its manifold edge (a, b),
//     vertex p          = slice.vertices(p)          + (v - value) * rate(p)
//     attribute p       = slice.vertex_attributes(p) + (v - value) * attribute_rates(p)
//     edge_parameter p  = slice.edge_parameter(p)    + (v - value) * parameter_rate(p)
//   which is slice(manifold, axis, v) up to rounding (Slicer::slice_in_interval
//   gives it bit for bit). Normals are not linear: recompute them from the moved
//   vertices (frame_vertex_normals).
struct IntervalFrame {
  int axis;
  double value;         // the value `slice` was cut at
  Slice slice;          // its vertex_edges(p) = (a, b) is the edge vertex p slides on; a < b
  double lo, hi;        // the topology interval around `value` (IntervalIndex::topology_interval)
  PointMatrix rate;     // P by D-1: d vertices / d value, (V(b) - V(a)) / (V(b, axis) - V(a, axis))
  VertexAttributes attribute_rates;  // per vertex attribute, P by its columns: d attribute / d value
  Eigen::VectorXd parameter_rate;    // P: d edge_parameter / d value, 1 / (V(b, axis) - V(a, axis))
};

// Keeps a manifold with what repeated slicing needs: one interval index per
// axis, each built on first use. Slicing the same manifold for every frame
// of a timeline then costs what each frame cuts. Safe to use from several
// threads at once: the first use of an axis builds its index once, and the
// others wait for it.
class Slicer {
 public:
  // Inputs:
  //   manifold  the manifold to slice, shared and never changed (not validated
  //             here: pass a validated one, Complex::validate)
  // Throws: InputError when manifold is null
  explicit Slicer(std::shared_ptr<const Complex> manifold);

  // Inputs:
  //   axis, value, stages  as the free slice()
  //   use_index            stab through the axis's interval index (built on first
  //                        use), else test every simplex
  // Outputs: the free slice()'s Slice
  // Throws: InputError as the free slice(), and for an axis outside 0..D-1
  Slice slice(int axis, double value, bool use_index = true, SliceStages* stages = nullptr);

  // Inputs: axis, value as slice()
  // Outputs: the free slice_shape(), through the axis's interval index
  // Throws: as slice()
  Slice slice_shape(int axis, double value);

  // Inputs:
  //   axis   0..D-1
  //   value  where to cut, inside a topology interval
  // Outputs: IntervalFrame: the frame at `value` with its topology interval and
  //   each vertex's rates
  // Throws: InputError when `value` is not finite or has no topology interval (it
  //   lies on a vertex coordinate or outside the manifold: the faces change
  //   there), and for what slice() rejects
  IntervalFrame interval_frame(int axis, double value);

  // Inputs:
  //   frame  an interval frame of this slicer (interval_frame)
  //   value  inside frame's topology interval
  // Outputs: the slice at `value`: frame.slice's faces, vertex edges and face
  //   data with the points, edge parameters, vertex attributes and normals
  //   computed at `value`, identical bit for bit to slice(frame.axis, value)
  // Throws: InputError when `value` is not finite or lies outside frame's
  //   topology interval (topology_interval(value) is another one, or none), or
  //   when frame's vertex edges are not edges (a, b), a < b, of this manifold
  //
  // The cost is a gather and a lerp per vertex: for the frames of a bake or
  // export that share a topology interval.
  Slice slice_in_interval(const IntervalFrame& frame, double value);

  // Inputs:
  //   axis  0..D-1
  // Outputs: the axis's interval index, built on first use (once, whichever
  //   threads ask at the same time)
  // Throws: InputError for an axis outside 0..D-1
  const IntervalIndex& index(int axis);

  // Outputs: the manifold
  // Throws: nothing
  const Complex& manifold() const { return *manifold_; }

 private:
  std::shared_ptr<const Complex> manifold_;
  std::vector<std::unique_ptr<IntervalIndex>> indices_;
  std::unique_ptr<std::once_flag[]> index_built_;  // one per axis
};

}  // namespace animanifold
