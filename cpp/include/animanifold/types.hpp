// Dense types shared by every module of the core.
//
// Everything dense is row-major so that C-contiguous numpy arrays cross the
// binding without copies: points are `#V by D` doubles (the last column is the
// axis of time), simplices are `#S by (k+1)` int32 vertex indices.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>

namespace animanifold {

using Index = std::int32_t;

// #V by D points (D = 2..4; the last column is time).
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// #S by (k+1) vertex indices of k-simplices.
using SimplexMatrix = Eigen::Matrix<Index, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Per-element attribute tables, keyed by name. Vertex attributes are floats,
// simplex attributes are integers (material index, source face, ...).
using VertexAttributes = std::map<std::string, PointMatrix>;
using SimplexAttributes = std::map<std::string, SimplexMatrix>;

using IndexVector = Eigen::Matrix<Index, Eigen::Dynamic, 1>;

}  // namespace animanifold
