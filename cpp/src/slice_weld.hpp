// Internal to slicing (slice_cut.cpp): numbering the cut's points, one per
// manifold edge or vertex, in the order the cut first meets them.
//
// The cut lists each point it meets as a key (a, b), a <= b, once per
// simplex, chunk by chunk. The weld gives every key the number of its
// point: points are numbered in order of their first key, so the result is
// what one thread walking the keys in order would give, for any thread count.
//
// Threads: each owns the keys of some lower vertices a (a hash of a picks the
// thread). Each chunk's keys are first grouped by owner (on the threads, chunk
// by chunk); then each thread walks its own keys, chunk by chunk in order,
// finding them through a per-vertex list of its points (a handful each)
// instead of a global hash. The first keys of points are then ranked in order,
// chunk by chunk.
#pragma once

#include "animanifold/complex.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace animanifold::slice_cut {

// The point at parameter s on manifold edge (a, b), a < b; a == b (s = 0)
// for a manifold vertex on the plane.
struct Point {
  Index a, b;
  double s;
};

// Inputs:
//   m, axis, value  the manifold and the plane {x_axis = value}
//   keys            per chunk, in order: its keys (a << 32 | b), a <= b, with
//                   b == a for a manifold vertex on the plane
// Outputs:
//   ids             per chunk (sized like keys): each key's point
//   points          the points, numbered in order of their first key, with
//                   their edge parameter (0 for a manifold vertex)
void weld(const Complex& m, int axis, double value, const std::vector<std::span<const std::uint64_t>>& keys,
          const std::vector<std::span<Index>>& ids, std::vector<Point>& points);

}  // namespace animanifold::slice_cut
