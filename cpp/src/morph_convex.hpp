// §8.4 at the exact coordinates: the fill between two convex shapes as a
// triangulation of the convex hull of S×{0} ∪ T×{span}, built from the hull's
// faces instead of a Delaunay fill of perturbed points.
//
// The Delaunay route decides everything on points perturbed by 1e-7 of the
// size. Where the inputs have flat sides (a cube's squares, a cylinder's
// caps, parallel sides of both), the hull's facets hold many points in one
// hyperplane, the perturbed fill triangulates them as if they bent, and once
// the exact coordinates are back some of its boundary is flat tets and folds
// (a cube → cylinder morph: 539 of 1,496 simplices flat, every checked frame
// running through itself). Here the hull's facets are found with exact
// predicates (coplanar boundary cells of an exact Delaunay triangulation of
// the points, grouped), every 2D face between two lateral facets that is
// not a triangle is triangulated as the star of its edges from a point
// inside it (once, for both facets), the faces in the planes t = 0 and
// t = span by the inputs' own triangles, each facet as the star of those from
// a point inside it, and the whole polytope as the star of its boundary from
// its centre (points added between the planes all at half the span): a triangulation
// whose every simplex is positive and whose boundary is the inputs at the
// ends. Every frame is then the convex shape (1-s)·S ⊕ s·T.
#pragma once

#include "animanifold/types.hpp"

#include <optional>

namespace animanifold {

struct ConvexFill {
  // The points given, then those added: the centres of the source's and the
  // target's caps (in their planes), of the hull's 2D faces and lateral
  // facets between the planes that are not simplices (on the boundary, at
  // half the span) and of the hull.
  PointMatrix points;
  SimplexMatrix simplices;  // #A by 5, each positive
  Index source_centre = -1, target_centre = -1;  // rows of `points`
};

// `P` (#P by 4): the source's vertices (rows 0..nS-1) at time 0, then the
// target's at time span > 0, as given (no Steiner point). `FS`, `FT` (#F by
// 3): the closed outward triangles of each, FT over P's rows (offset by nS).
// Returns the fill, or nothing when an input is not convex (bent inwards at
// an edge by more than rounding — 1e-6 of its size, so that rotated flat
// sides count as flat — or enclosing other than its hull once: in parts, or
// wound twice) or the construction fails one of its own checks; the caller
// then takes the Delaunay route. Hull facets bent by rounding are grouped
// as one, like flat ones.
std::optional<ConvexFill> convex_hull_fill(const PointMatrix& P, Index nS, const SimplexMatrix& FS,
                                           const SimplexMatrix& FT);

}  // namespace animanifold
