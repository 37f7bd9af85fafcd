// Hole spaces (§8.6.5) and the solid Boolean operations that let frames of a
// morph honour them (validity 3 of §8.3).
//
// For a closed shape C, its hole space is H_C = CH(C) \ C: the part of its
// convex hull that the shape does not fill (the tunnel of a torus, the
// concavities of a bean). A morph from S to T keeps the holes both share by
// subtracting H = H_S ∩ H_T from every in-between frame: frame \ H.
//
// A solid is given by its boundary, libigl style, as Eigen matrices:
//   3D: V #V by 3 points, F #F by 3 triangles, closed, consistently oriented
//       with outward normals (right-hand rule);
//   2D: V #V by 2 points, F #F by 2 oriented edges forming closed loops,
//       counter-clockwise around the solid (outer loops counter-clockwise,
//       loops around holes clockwise).
// Results have the same form (2D results as loops around each polygon,
// outer boundaries counter-clockwise, holes clockwise; a point where two
// loops touch appears once per loop), numbered canonically: vertices in
// lexicographic order, faces sorted (equal results are equal arrays, which
// CGAL's own numbering does not guarantee). An empty solid has no rows.
// Not bit-for-bit reproducible in 3D: where faces of the two operands share
// coordinates exactly (a shape's faces on its own hull), CGAL's corefinement
// breaks ties between their bounding boxes by the boxes' addresses, so how
// such flat regions are triangulated (and which points the corefinement adds
// there) can differ between calls, processes and thread counts; every result
// bounds the same solid (volumes agree to rounding).
//
// The operations are exact: CGAL's convex hulls, polygon-mesh corefinement
// (3D) and Boolean set operations on polygons (2D) with an exact-constructions
// kernel; the results are rounded to doubles once, at the end.
//
// Operands that come from slicing may hold faces of nearly zero area (height
// below 1e-12 of the operand's size) where a nearly flat simplex was cut;
// those are made exactly degenerate and collapsed or flipped away first
// (the geometry moves by at most that much). Pinched operands (sheets that
// touch at a vertex) are split there. Where the second operand cannot touch
// the first (see Subtraction::unchanged), no Boolean operation runs at all.
//
// Errors: a malformed array (wrong width, index out of range, non-finite
// point) is an InputError. An operand CGAL cannot work on (not closed, an edge
// in more than two faces, inconsistent orientation, self-intersecting, a
// non-simple loop) or a result that is not a manifold throws BooleanError,
// whose message names the operand ("the frame", "the hole space", ...) and
// the problem.
//
// The Boolean operations (hole_space, intersect_solids, subtract_solid) run in
// a child process: CGAL's corefinement can loop for ever on some inputs, and a
// loop must not hang Blender. The `interrupter` is polled before and about
// every 0.1 s while the child runs (Cancelled stops it, as Esc or Ctrl-C do),
// and a child that runs far past what a Boolean of its size takes (a minute
// and more) is killed: TimeLimitError says so.
#pragma once

#include "animanifold/errors.hpp"
#include "animanifold/progress.hpp"
#include "animanifold/types.hpp"

#include <stdexcept>
#include <string>

namespace animanifold {

// The boundary of a solid in R^3 (triangles) or R^2 (oriented edges).
struct Solid {
  PointMatrix vertices;  // #V by d
  SimplexMatrix faces;   // #F by d
  // Outputs: whether the solid has no faces. Throws: nothing
  bool empty() const { return faces.rows() == 0; }
};

// Inputs:
//   V, F         the closed outward shape C: #V by d points, #F by d faces (d = 3 or 2)
//   interrupter  polled while CGAL runs (see above)
// Outputs:
//   Solid: the boundary of CH(C) \ C, empty when C is convex
// Throws: InputError when C intersects itself; BooleanError when CGAL refuses it; TimeLimitError
//   when it runs past its time limit; Cancelled when the interrupter says so
//
// The hole space H_C = CH(C) \ C of the closed outward shape C = (V, F)
// (3D mesh or 2D polygons), as a closed outward solid; empty (0 rows) when C
// is convex. Only the vertices that faces use count for the hull. C must not
// intersect itself (checked).
// In 3D, quads of C on its hull that are planar up to rounding but split
// along the other diagonal than the hull's facets are flipped first (C
// changes by a sliver of rounding thickness, not counted as a hole). Where
// slivers of C's own triangulation still touch one another along edges, so
// that the exact difference is not a manifold, two retries follow: with every
// dent of C's triangulation between four hull vertices flipped away (those
// dents are not holes), then with the hull shrunk by 2^-24 (6e-8) of its size
// about its centroid (slivers thinner than that disappear, and real holes
// lose a layer about as thick under the hull; the result has features of
// that size, which later Booleans may refuse after rounding).
Solid hole_space(const PointMatrix& V, const SimplexMatrix& F, const Interrupter& interrupter = {});

// Inputs:
//   VA, FA, VB, FB  the two solids' boundaries
//   interrupter     polled while CGAL runs
// Outputs:
//   Solid: A ∩ B
// Throws: InputError for mismatched dimensions or invalid boundaries; BooleanError when CGAL refuses;
//   TimeLimitError when it runs past its time limit; Cancelled when the interrupter says so
//
// The solid A ∩ B (both 3D or both 2D). Empty when they do not overlap.
Solid intersect_solids(const PointMatrix& VA, const SimplexMatrix& FA, const PointMatrix& VB,
                       const SimplexMatrix& FB, const Interrupter& interrupter = {});

// subtract_solid:
// Inputs:
//   V, F         the frame (a closed outward boundary)
//   VH, FH       the solid to subtract
//   interrupter  polled while CGAL runs
// Outputs:
//   Subtraction: the result and whether the frame is unchanged
// Throws: InputError for mismatched dimensions; BooleanError when CGAL refuses; TimeLimitError
//   when it runs past its time limit; Cancelled when the interrupter says so
//
// The frame minus the solid H: (V, F) \ (VH, FH).
struct Subtraction {
  Solid solid;
  // True when H cannot change the frame: H is empty, the bounding boxes do
  // not overlap, or the two boundaries do not meet and neither solid lies
  // inside the other. `solid` is then a copy of the frame (same vertices and
  // faces in the same order), and callers holding the frame may keep it.
  bool unchanged = false;
};
Subtraction subtract_solid(const PointMatrix& V, const SimplexMatrix& F, const PointMatrix& VH,
                           const SimplexMatrix& FH, const Interrupter& interrupter = {});

// Inputs:
//   V, F  a triangle mesh in R^3
// Outputs:
//   whether two faces cross
// Throws: InputError (see below)
//
// Whether the triangle mesh (V, F) in R^3 intersects itself: two faces
// meet other than at the vertices and edges they share (CGAL's exact test).
// Faces of zero area count as intersecting. (V, F) must be a 2-manifold
// (closed or not); InputError otherwise.
bool intersects_itself(const PointMatrix& V, const SimplexMatrix& F);

// Inputs:
//   V, F    a closed outward triangle mesh in R^3
//   points  #P by 3
// Outputs:
//   #P flags: inside or on the mesh
// Throws: InputError (see below)
//
// Whether each of the points (#P by 3) lies inside the closed outward
// triangle mesh (V, F) in R^3, or on it; a point in a cavity or a tunnel is
// outside. CGAL's Side_of_triangle_mesh (exact predicates) over an AABB tree:
// O((#F + #P) log #F), where summing solid angles costs #P x #F. (V, F) must
// be a closed 2-manifold, consistently oriented; InputError otherwise.
Eigen::Array<bool, Eigen::Dynamic, 1> points_inside_solid(const PointMatrix& V, const SimplexMatrix& F,
                                                          const PointMatrix& points);

// Inputs:
//   V, F  a closed outward boundary
// Outputs:
//   its signed volume (3D) or area (2D)
// Throws: nothing
//
// The volume (3D) or area (2D) enclosed by a closed, outward boundary:
// negative when it is inside out, 0 for an empty solid.
double solid_measure(const PointMatrix& V, const SimplexMatrix& F);

}  // namespace animanifold
