// Whether a set of simplices tiles a convex region exactly once: the
// certificate that a triangulation is embedded (no two simplices overlap)
// and leaves no gap. The region is the convex hull of the points the
// simplices use (R^3), or that hull times the interval of their times (R^4,
// time last: a slab of prisms between two layers of the same points).
//
// The argument (a degree count): when every simplex is positive (exact
// orientation), every facet inside is shared by exactly two simplices that
// list it with opposite orientations, and every facet of the boundary lies
// on the region's boundary, then every point of the region inside no facet
// lies in the same number k of simplices: crossing an inner facet leaves one
// simplex and enters the other. The volumes then sum to k times the
// region's, and a sum equal to the region's volume means k = 1. The field
// morph's validity stage certifies its space-time triangulation with it
// (morph_field.hpp).
#pragma once

#include "animanifold/types.hpp"

#include <cstdint>
#include <string>

namespace animanifold {

struct ConvexCover {
  std::int64_t simplices = 0;
  std::int64_t not_positive = 0;           // flat or inverted (exact orientation)
  std::int64_t unmatched_facets = 0;       // in three or more simplices, or two on one side
  std::int64_t repeated_vertices = 0;      // simplices naming a vertex twice
  std::int64_t stray_boundary_facets = 0;  // boundary facets off the region's boundary
  double volume_ratio = 0;                 // summed volumes over the region's
  // Outputs: whether the simplices tile the region once.
  bool covers_once() const;
  // Outputs: what failed, in words ("" when covers_once()).
  std::string failure() const;
};

// Inputs:
//   points     #P by D (D = 3, or 4 with time last)
//   simplices  #S by D+1 indices into points
// Outputs:
//   ConvexCover: the counts above over the region (the convex hull of the
//   used points in R^3; in R^4 the hull of their first three coordinates
//   times the interval of their last)
// Throws: InputError for another D, for simplices that are not D+1 wide,
//   for an index outside points
ConvexCover check_convex_cover(const PointMatrix& points, const SimplexMatrix& simplices);

}  // namespace animanifold
