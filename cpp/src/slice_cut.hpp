// Internal to slice.cpp: cutting the candidate simplices by the hyperplane
// (the table of Figure 2.6) and welding their cut points, one per manifold
// edge or vertex.
//
// The cut runs in parallel over chunks of a fixed number of candidates; each
// chunk lists the points it meets as (edge) keys. The weld then walks the
// chunks' keys in order and numbers each key's point by its first key
// (slice_weld.hpp), so the output is what one thread cutting the candidates
// in order would give, for any thread count.
#pragma once

#include "animanifold/complex.hpp"
#include "animanifold/slice.hpp"
#include "slice_weld.hpp"

#include <vector>

namespace animanifold::slice_cut {

struct CutFaces {
  int n = 0;                  // corners per face: 3 (tets) or 2 (triangles)
  std::vector<Point> points;  // the welded points, in the order the cut first meets them
  std::vector<Index> corners;  // n per face, into points
  std::vector<Index> simplex;  // per face: the simplex it was cut from
  // Whether a point is a manifold vertex (a == b). When none is, no face
  // collapsed or cancelled: every point is a corner of some face.
  bool on_vertices = false;
};

// Inputs:
//   m                  tets in R^4 or triangles in R^3
//   axis, value        the hyperplane {x_axis = value}
//   on_plane_is_above  whether a vertex on the plane counts as above it
//   candidates         the simplices to cut, in order
//   stages             optional: receives the seconds of the cut and of the weld
// Outputs: each candidate's faces (none when it lies on one side) with
//   welded corners; faces whose corners repeat a point (zero area) dropped
CutFaces cut_and_weld(const Complex& m, int axis, double value, bool on_plane_is_above,
                      const std::vector<Index>& candidates, SliceStages* stages = nullptr);

// A face and its exact reverse on the same vertices bound nothing: they are
// the two sides of a zero-width slit (where a manifold that opens a hole or a
// split right after this time is cut at that time). Removes such pairs so the
// slice is the limit surface, not the slit.
void cancel_opposite_pairs(CutFaces& faces);

// The points that `corners` use, in order, with `corners` renumbered onto
// them (all of 0..count-1, untouched, when every point is used).
std::vector<Index> used_points(std::vector<Index>& corners, Index count);

}  // namespace animanifold::slice_cut
