// The push of the skeleton method (§8.6.3) as a layer between an input's
// plane and the fill.
//
// The fill A (Theorem 5.2.1) joins the triangulation K of each input's plane
// (its cells: inside the input, or outside it with a free vertex) to the
// other plane. Pushing the free vertices into time inside A itself deforms
// A's simplices, and the thinnest of them — slivers between points in two
// parallel planes are everywhere in a Delaunay fill — stop the push at
// once: on a sphere -> 3holes.off three free vertices in four go less than
// a tenth of their way, the mean push is 0.2 % of the range, and the
// target's holes open in the last 2 % of it, through bubbles.
//
// Instead the fill's plane moves into time by the layer's thickness, and the
// layer between it and the end is made of prisms over K's cells, each split
// into n+1 simplices by a global vertex order (stitch.hpp's staircase, so
// that neighbouring prisms agree). A prism keeps a positive volume whatever
// the heights of its bottom corners, as long as each stays below the top:
// the free vertices' bottom copies go to their heights with every simplex
// positive, which is what §8.6.3's binary search checks for, and the frames
// in the layer are the sublevel sets of a height field over K: the source's
// concavities and holes fill after t0, the target's empty before t1.
//
// The heights follow the distance from the input (all the way from a share
// of the farthest free vertex's distance on, never nothing), so the frames
// in the layer are close to offsets of the input: a hole opens along its
// axis first and widens, a thin film between the input and its hull empties
// last. Then they are levelled: a vertex above every path from it to the
// hull comes down to the best path's lowest height (a peak of the distance
// field the cells do not join to the outside would be the last of its
// region to empty: a bubble in the frames), one below every path to the
// input comes up to the best path's highest (else an island). Outside
// regions that do not reach K's boundary (a cavity inside the input) keep
// their heights: a bubble by nature.
//
// Cells outside the input on K's boundary that are flat to rounding (four
// points of a nearly planar stretch of the hull: a sliver between the hull's
// two triangles and the other diagonal inside) are left out of the layer:
// the heights, linear on each, differ across them, and the frames would
// fold there within their plane. The fill's cell under each shows at the
// layer's top as a face of no volume.
//
// Faces outside the input without a free vertex (a chord across a hole,
// whose ends are on the input) would stay at the end as a thread or
// membrane; each is split at a free point first (split_faces, in K), and so
// are long edges outside the input (a hole opens only as finely as its
// cells are). The layer is built in two parts: prisms over the split K from
// the end to most of the layer's thickness, then prisms over K itself, split
// at their bottom the same way, up to the fill (the split points end there).
#pragma once

#include "morph_skeleton.hpp"

#include <vector>

namespace animanifold {

struct PlaneLayer {
  SimplexMatrix simplices;      // #L by n+2 over the morph's points, positively oriented
  std::vector<Index> end_copies;  // the copies at the end of K's vertices that are not free (the input's plane)
  std::vector<Index> free_copies;  // the copies at their heights of the free vertices and the split points
  Index split_faces = 0;           // faces outside the input without a free vertex, split
  Index refinement_points = 0;     // points splitting long edges outside the input
  Index peeled_slivers = 0;        // cells flat to rounding on K's boundary, left out (peel_boundary_slivers)
  Index free_vertices = 0;        // free vertices of K, split points included
  Index sealed_vertices = 0;      // of those, in outside regions that do not reach K's boundary
  Index levelled_vertices = 0;    // of those, moved off their distance's height (no bubble, no island)
  double smallest = 0, mean = 0, largest = 0;  // heights of the free vertices, in units of the last axis
};

// The layer between the plane of the points flagged `in_plane` (their
// cells `plane`, classify_plane, over the rows of `P`) at `end_time` (t0 or
// t1) and the fill, which must be at `fill_time` already: the plane's
// points of `P` (#P by n+1) are the fill's copies, and their first n
// coordinates (exact) are the layer's. Appends the layer's points to `P`.
// `fill_points` are the coordinates the fill's combinatorics were decided
// on (the cells' orientation is read there). The free vertices at K's
// boundary go most of the way from the end towards the fill.
PlaneLayer plane_layer(PointMatrix& P, const PointMatrix& fill_points, const PlaneCells& plane,
                       const PointMatrix& input_points, const SimplexMatrix& input_faces, double end_time,
                       double fill_time);

// The n+1 simplices of the prism over `cell` (n+1 ids, positively oriented
// in R^n) between the copies lower[i] and upper[i] of cell[i] (upper later
// in time), split along the order of the cell's ids (so that two prisms
// over neighbouring cells cut their shared side alike); appended to `out`
// as rows of n+2 ids, each positively oriented while every lower copy lies
// below its upper copy.
void append_prism(const Index* cell, int corners, const Index* lower, const Index* upper, std::vector<Index>& out);

}  // namespace animanifold
