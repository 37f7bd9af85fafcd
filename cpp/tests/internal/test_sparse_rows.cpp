// Row-major sparse matrices built on all threads (sparse_rows.hpp): rows of a
// fixed width come out sorted with repeated columns summed, as Eigen's
// setFromTriplets gives them, and the product by row blocks is Eigen's
// product, with the same bits on any thread count.
#include "sparse_rows.hpp"

#include "animanifold/threads.hpp"

#include "../fixtures.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace animanifold;

namespace {

// Row r's entries: columns (7 r + 3 e) mod columns, some repeated within the row.
void entries_of(Index r, Index columns, int width, Index* column, double* value) {
  for (int e = 0; e < width; ++e) {
    column[e] = (7 * r + 3 * (e % 4)) % columns;
    value[e] = 0.1 * (e + 1) + 1.0 / (r + 1);
  }
}

RowSparseMatrix by_triplets(Index rows, Index columns, int width) {
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<Index> column(width);
  std::vector<double> value(width);
  for (Index r = 0; r < rows; ++r) {
    entries_of(r, columns, width, column.data(), value.data());
    for (int e = 0; e < width; ++e) triplets.emplace_back(r, column[e], value[e]);
  }
  RowSparseMatrix M(rows, columns);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

}  // namespace

TEST(SparseRows, RowsOfAWidthAreWhatSetFromTripletsGives) {
  const Index rows = 3000, columns = 500;
  const int width = 6;  // entries 4 and 5 repeat the columns of 0 and 1
  const RowSparseMatrix expected = by_triplets(rows, columns, width);
  const int before = thread_count();
  for (int count : {1, 2, 3}) {
    set_thread_count(count);
    const RowSparseMatrix built = rows_of_width(rows, columns, width, [&](Index r, Index* c, double* v) {
      entries_of(r, columns, width, c, v);
    });
    EXPECT_TRUE(built.isCompressed());
    EXPECT_TRUE(fixtures::same_sparse_bits(built, expected)) << count << " threads";
  }
  set_thread_count(before);
  EXPECT_EQ(expected.nonZeros(), rows * 4);
}

TEST(SparseRows, TheProductByRowBlocksIsEigensProductOnAnyThreadCount) {
  const RowSparseMatrix A = by_triplets(2000, 700, 6), B = by_triplets(700, 300, 5);
  const RowSparseMatrix expected = A * B;
  const int before = thread_count();
  for (int count : {1, 2, 3}) {
    set_thread_count(count);
    EXPECT_TRUE(fixtures::same_sparse_bits(product_by_row_blocks(A, B), expected)) << count << " threads";
  }
  set_thread_count(before);
}
