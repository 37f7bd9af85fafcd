// Checks the core's public entry points share: index arrays against the
// points they index, and counts against the 32-bit Index (types.hpp). Each
// entry point checks its inputs before it touches memory through them, so
// C++ callers are protected as well as Python's.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "animanifold/types.hpp"

namespace animanifold {

// Inputs:
//   rows   #R by c vertex indices (simplices, faces, segments, ...)
//   count  how many points they index
//   what   how a message names one row ("face", "simplex", "the source's face")
// Throws: InputError "<what> <r> refers to vertex <v>, outside 0..<count-1>"
//   for the first index outside [0, count)
void check_indices(const Eigen::Ref<const SimplexMatrix>& rows, Eigen::Index count, const char* what);

// Inputs:
//   count  a number of points or simplices, in 64 bits
//   what   how a message names them ("manifold points")
// Outputs: count as an Index
// Throws: InputError when count is negative or larger than the largest
//   Index (2^31 - 1): such arrays cannot be indexed by the core's int32s.
Index checked_index_count(std::int64_t count, const char* what);

}  // namespace animanifold
