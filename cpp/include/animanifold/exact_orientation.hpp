// The exact sign of a simplex's orientation (CGAL's filtered predicates).
//
// The fill's combinatorics are decided by exact predicates (delaunay_exact);
// whatever is built on them afterwards (the stellar splits of
// morph_skeleton.hpp) must keep every simplex positive by the same measure,
// not by a rounded determinant: slivers of the fill have volumes far below
// the rounding of a determinant in doubles, and one that a new point tips
// over by an ulp is inverted for good once free vertices move.
#pragma once

#include "animanifold/types.hpp"

namespace animanifold {

// Inputs:
//   points   #P by D, D = 2, 3 or 4
//   corners  D+1 indices into points
// Outputs:
//   -1, 0 or +1
// Throws: InputError for another D
//
// The sign (-1, 0, +1) of det[p1 - p0, ..., pD - p0] for the D+1 rows
// `corners` of `points` (#P by D, D = 2, 3 or 4), computed exactly.
int exact_orientation(const PointMatrix& points, const Index* corners);

}  // namespace animanifold
