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

inline constexpr double kMaxCoordinate = 1e30;

// Inputs:
//   points  #P by d
//   what    how a message names one row ("the surface's vertex", "query point")
// Outputs: nothing
// Throws: InputError "<what> <p> has a coordinate of <x>, beyond +-1e+30" (or
//   "is not finite") for the first row that is not finite or not within
//   kMaxCoordinate
void check_coordinates(const Eigen::Ref<const PointMatrix>& points, const char* what);

}  // namespace animanifold
