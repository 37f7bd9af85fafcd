// Removing simplices from the boundary of a triangulated ball so that it
// stays a ball (shelling steps).
//
// The morph's fill has slivers along flat facets of the convex hull that
// hold points of both planes in one hyperplane (a hull edge of a plate with
// collinear points, a flat side both inputs share): cells proper for exact
// predicates but flat within roundoff. Taken off the boundary, nothing
// changes but the triangulation of that flat facet — if each removal is a
// shelling step: where a sliver meets the boundary elsewhere than in its own
// boundary facets (a vertex or an edge of it on the boundary already),
// removing it would pinch the boundary into a non-manifold.
#pragma once

#include "animanifold/types.hpp"

#include <functional>
#include <vector>

namespace animanifold {

// Inputs:
//   S           #S by k+1 simplices of a triangulated ball
//   candidates  rows of S that may be removed
//   may_open    whether a boundary facet (sorted vertex ids) may open
// Outputs:
//   per row of S, whether it was removed
// Throws: InputError for simplices of more than 4 dimensions
//
// `S` (#S by k+1, k <= 4): the simplices of a triangulated ball (its
// boundary facets, those in one simplex only, a closed manifold).
// `candidates`: rows of S that may be removed. A candidate is removed when
// its facets on the current boundary are a nonempty proper subset of its
// facets, `may_open` accepts each of them (sorted vertex ids, k of them),
// and no face of the candidate that holds every vertex opposite those
// facets lies on the boundary already. Removals expose the candidate's other
// facets; candidates are tried again until none can go. Returns, per row of
// S, whether it was removed.
std::vector<bool> shell_off(const SimplexMatrix& S, const std::vector<Index>& candidates,
                            const std::function<bool(const Index* facet)>& may_open);

}  // namespace animanifold
