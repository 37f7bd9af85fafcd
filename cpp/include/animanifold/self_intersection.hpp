// Whether a closed shape overlaps itself: a morph's inputs must not (§8.3).
#pragma once

#include "animanifold/types.hpp"

#include <utility>
#include <vector>

namespace animanifold {

// Inputs:
//   V          #V by d points (d = 3 or 2)
//   F          #F by d faces (triangles, or segments)
//   max_pairs  at most this many pairs (0: all)
//   tolerance  depth below which a crossing is left out (0: none)
// Outputs:
//   pairs of face indices that cross; empty when the shape is simple
// Throws: InputError when the shape is not a manifold of the right dimension,
//   or a face refers to a vertex outside V
//
// Pairs of faces of the closed, manifold shape (V, F) that intersect other
// than along the edges and corners they share: triangles in R^3 (CGAL's
// Polygon_mesh_processing::self_intersections on a Surface_mesh) or
// segments in R^2 (pairwise, with CGAL's exact predicates). At most
// `max_pairs` pairs are returned (0: all). Empty when the shape is simple.
//
// `tolerance` > 0 leaves out pairs that pass through each other by no more
// than that: the smaller of each face's depth through the other's plane
// (line), or, for two faces in one plane to within it, how wide their
// overlap is (twice its area over its perimeter; in 2D its length). A
// frame's coordinates are rounded: where a cell of the manifold is flat to
// rounding, neighbouring faces touch, and the exact test finds them crossing
// by 1e-16 of the size. 0 keeps every pair the exact test finds (what an
// input is held to).
std::vector<std::pair<Index, Index>> self_intersections(const PointMatrix& V, const SimplexMatrix& F,
                                                        std::size_t max_pairs = 1, double tolerance = 0.0);

}  // namespace animanifold
