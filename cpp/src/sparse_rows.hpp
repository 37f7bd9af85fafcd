// Private: building row-major sparse matrices on all threads: from rows of a
// fixed number of entries, and as a product by blocks of rows. Each row is
// computed alone, in the same order whatever the blocks, so the bits do not
// depend on the thread count.
#pragma once

#include "animanifold/types.hpp"

#include <Eigen/SparseCore>

#include <functional>

namespace animanifold {

using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Inputs:
//   rows, columns  the matrix's size
//   width          entries each row is given
//   fill           fill(row, columns, values) writes the row's `width` entries
//                  (any order; called from several threads at once)
// Outputs:
//   the compressed matrix, each row's columns ascending; entries given twice in
//   a row are summed in the order given (as Eigen's setFromTriplets sums them)
// Throws: nothing of its own
RowSparseMatrix rows_of_width(Index rows, Index columns, int width,
                              const std::function<void(Index, Index*, double*)>& fill);

// Outputs: A B, compressed, computed by blocks of A's rows on thread_count()
//   threads (Eigen's product on each block: the same bits as A * B)
// Throws: nothing of its own
RowSparseMatrix product_by_row_blocks(const RowSparseMatrix& A, const RowSparseMatrix& B);

}  // namespace animanifold
