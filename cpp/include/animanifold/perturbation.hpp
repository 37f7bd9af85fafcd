// Perturbations that are functions of position.
//
// The morph computes its combinatorics on points moved off degeneracies by a
// tiny amount (see morph.cpp). A random offset per point index would treat
// two copies of one point differently: where the source and the target share
// vertices (identical shapes, the rockerArm test of Figure 8.9, or shapes
// that share a part), the copies at t0 and t1 would be perturbed apart, the
// fill would cut the vertical rectangle between two shared vertices' columns
// into slivers, and those slivers are flat once the exact coordinates come
// back (zero-area faces in every frame). An offset that depends only on the
// exact coordinates (a hash of their bits) moves both copies alike: the
// columns stay exactly vertical, the exact Delaunay fill sees the degeneracy
// and resolves it symbolically with proper simplices, as stitching does.
// The offsets are deterministic, independent of point order, and look
// uniformly random in [-scale, scale] per coordinate.
#pragma once

#include "animanifold/types.hpp"

#include <string>
#include <utility>
#include <vector>

namespace animanifold {

// Inputs:
//   p          d coordinates
//   component  which coordinate's offset
//   salt       varies the hash between uses
// Outputs:
//   an offset in [-1, 1]
// Throws: nothing
//
// An offset in [-1, 1] for coordinate `component` of the point `p` (`d`
// coordinates), a function of p's exact bits (-0.0 and 0.0 alike) and `salt`.
double position_hash_offset(const double* p, int d, int component, std::uint64_t salt);

// Inputs:
//   points  #P by d
//   scale   the largest offset per coordinate
//   salt    as position_hash_offset
// Outputs:
//   #P by d perturbed points
// Throws: nothing
//
// `points` (#P by d) each moved by scale * position_hash_offset, per coordinate.
PointMatrix perturbed_by_position(const PointMatrix& points, double scale, std::uint64_t salt);

// Inputs:
//   attempts  (perturbation, what failed), in the order tried
// Outputs:
//   one message naming each failure once
// Throws: nothing
//
// What failed at each perturbation a retry tried, as one message: each
// failure once, with all the perturbations (fractions of the size) it
// happened at — "the source: TetGen ... (it did not finish within 13 s) with
// the inputs perturbed by 1e-07 and 1e-06 of their size; then the source:
// TetGen moved input point 6865 at 1e-05". `attempts`: (perturbation, what
// failed), in the order tried.
std::string failed_perturbations(const std::vector<std::pair<double, std::string>>& attempts);

}  // namespace animanifold
