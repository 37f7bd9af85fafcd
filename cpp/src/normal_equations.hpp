// Private: the pieces of the Deformer's least-squares system A x = b with
// some columns of A fixed (anchors and handles): A's columns split into free
// and constrained ones, and the normal matrix AᵀA of the free part, on all
// threads with the same bits for any thread count.
#pragma once

#include "animanifold/types.hpp"

#include <Eigen/SparseCore>

#include <vector>

namespace animanifold {

using ColumnSparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Inputs:
//   A           rows by vertices, compressed, each row's columns ascending
//   column      per vertex: its free unknown (>= 0, ascending with the vertex), or
//               -(its constraint) - 2
//   free_count, constraint_count  how many of each `column` names
// Outputs:
//   free_t       free_count by rows: column r holds row r of A's free entries
//   constrained  rows by constraint_count: A's constrained entries
// Throws: nothing (`column` is the caller's, consistent with A)
void split_columns(const RowSparse& A, const std::vector<Index>& column, Index free_count, Index constraint_count,
                   ColumnSparse& free_t, RowSparse& constrained);

// Inputs:
//   free_t  unknowns by rows (A's free part, transposed), compressed
// Outputs:
//   the lower triangle (diagonal included) of free_t free_tᵀ = AᵀA, compressed.
//   Its columns are computed in blocks on thread_count() threads; each entry
//   is summed over A's rows in ascending order whatever the blocks, so the
//   bits do not depend on the thread count.
// Throws: nothing
ColumnSparse normal_matrix_lower(const ColumnSparse& free_t);

}  // namespace animanifold
