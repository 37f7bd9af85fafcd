// Whether a closed shape overlaps itself: a morph's inputs must not (§8.3).
#pragma once

#include "animanifold/types.hpp"

#include <utility>
#include <vector>

namespace animanifold {

// Pairs of faces of the closed, manifold shape (V, F) that intersect other
// than along the edges and corners they share: triangles in R^3 (CGAL's
// Polygon_mesh_processing::self_intersections on a Surface_mesh) or
// segments in R^2 (pairwise, with CGAL's exact predicates). At most
// `max_pairs` pairs are returned (0: all). Empty when the shape is simple.
std::vector<std::pair<Index, Index>> self_intersections(const PointMatrix& V, const SimplexMatrix& F,
                                                        std::size_t max_pairs = 1);

}  // namespace animanifold
