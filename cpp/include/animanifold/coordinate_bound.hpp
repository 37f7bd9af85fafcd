// The largest coordinate the core's geometry takes, and its check.
//
// The morph's stages multiply up to four coordinate differences (4D
// orientations and volumes) and the distance queries square them; beyond this
// bound those products overflow to infinity, and CGAL's exact predicates,
// converting an infinity to a rational, make GMP stop the process (SIGFPE).
// No scene comes near it: it is a guard against garbage, not a limit of use.
#pragma once

#include <Eigen/Core>

#include "animanifold/types.hpp"

namespace animanifold {

// What the core takes from its callers (shapes, times).
inline constexpr double kMaxCoordinate = 1e30;
// What the core computes with, checked where CGAL takes it (distance queries):
// points derived from inputs within kMaxCoordinate (a padded box, a lattice)
// stay far inside it, and fourth powers of such coordinates stay finite.
inline constexpr double kMaxDerivedCoordinate = 1e60;

// Inputs:
//   points  #P by d
//   what    how a message names one row ("the surface's vertex", "query point")
//   bound   the largest magnitude allowed
// Outputs: nothing
// Throws: InputError "<what> <p> has a coordinate of <x>, beyond +-<bound>"
//   (or "is not finite") for the first row that is not finite or not within
//   `bound`
void check_coordinates(const Eigen::Ref<const PointMatrix>& points, const char* what,
                       double bound = kMaxCoordinate);

}  // namespace animanifold
