// Corner charts: the bookkeeping that gives a morph's vertices the inputs'
// UV maps (python/animanifold/morph_surface.py, which documents the rules).
// Every corner of a simplex reads the UV map in its simplex's face; a vertex
// is split where the charts its corners read disagree. A morph has millions
// of corners and each vertex only a few pairs, so the corners are counted
// by vertex and only each vertex's pairs are sorted.
#pragma once

#include <Eigen/Core>

#include "animanifold/types.hpp"

namespace animanifold {

// The distinct (vertex, face) pairs the corners of `simplices` (#S by k,
// indices below `vertices`) use, where every corner of simplex s takes
// `face(s)` (>= 0): ascending by vertex, then by face, and each corner's
// pair (#S by k). These are numpy's unique over vertex * faces + face, with
// its inverse.
struct VertexFacePairs {
  IndexVector vertex, face;
  SimplexMatrix corner_pair;
};
VertexFacePairs vertex_face_pairs(const SimplexMatrix& simplices, const IndexVector& face, Index vertices);

// Numbers items (the pairs above) so that items of one `owner` (a vertex's
// pairs of one input) whose UVs (`uv`, #items by 2) agree share a number.
// In the order of (owner, u, v), and then again of (owner, v, u), each item
// is joined to the one after it when both have the same owner and both
// coordinates differ by at most the first one's `tolerance`; the numbers
// are the groups those joins make, counted 0, 1, ... in the order of each
// group's first item. Ties in a sort keep the items' order, and a NaN sorts
// after every number and joins nothing, as in numpy's lexsort.
IndexVector chart_labels(const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>& owner,
                         const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv,
                         const Eigen::VectorXd& tolerance);

}  // namespace animanifold
