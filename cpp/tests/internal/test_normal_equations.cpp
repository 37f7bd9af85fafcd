// The Deformer's normal equations (normal_equations.hpp): the column split
// keeps every entry of A on its side, and the normal matrix is the lower
// triangle of AᵀA, with the same bits on any thread count.
#include "normal_equations.hpp"

#include "animanifold/threads.hpp"

#include <Eigen/Dense>
#include "../fixtures.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace animanifold;

namespace {

// Rows of 3-8 entries over `columns` columns, like a Laplacian's rows.
RowSparse random_rows(int rows, int columns, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_int_distribution<int> width(3, 8), column(0, columns - 1);
  std::uniform_real_distribution<double> value(-1, 1);
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < rows; ++r) {
    const int count = width(generator);
    for (int e = 0; e < count; ++e) entries.emplace_back(r, column(generator), value(generator));
  }
  RowSparse A(rows, columns);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

}  // namespace

TEST(NormalEquations, TheSplitPutsEachEntryOnItsSide) {
  const RowSparse A = random_rows(500, 120, 3);
  // Every fifth vertex is constrained, numbered backwards (constraint order is the caller's).
  std::vector<Index> column(120);
  Index free_count = 0, constraint_count = 0;
  for (Index v = 0; v < 120; ++v) column[v] = v % 5 == 0 ? -1 : free_count++;
  for (Index v = 119; v >= 0; --v)
    if (column[v] == -1) column[v] = -(constraint_count++) - 2;
  ColumnSparse free_t;
  RowSparse constrained;
  split_columns(A, column, free_count, constraint_count, free_t, constrained);
  ASSERT_EQ(free_t.nonZeros() + constrained.nonZeros(), A.nonZeros());
  const Eigen::MatrixXd dense = Eigen::MatrixXd(A), free = Eigen::MatrixXd(free_t), fixed = Eigen::MatrixXd(constrained);
  for (Index v = 0; v < 120; ++v) {
    const Eigen::VectorXd expected = dense.col(v);
    const Eigen::VectorXd got = column[v] >= 0 ? Eigen::VectorXd(free.row(column[v]).transpose())
                                               : Eigen::VectorXd(fixed.col(-column[v] - 2));
    EXPECT_EQ(got, expected) << "vertex " << v;
  }
  // Compressed and sorted, as CHOLMOD and Eigen's products expect.
  for (Eigen::Index c = 0; c < free_t.cols(); ++c)
    for (int e = free_t.outerIndexPtr()[c] + 1; e < free_t.outerIndexPtr()[c + 1]; ++e)
      EXPECT_LT(free_t.innerIndexPtr()[e - 1], free_t.innerIndexPtr()[e]);
  for (Eigen::Index r = 0; r < constrained.rows(); ++r)
    for (int e = constrained.outerIndexPtr()[r] + 1; e < constrained.outerIndexPtr()[r + 1]; ++e)
      EXPECT_LT(constrained.innerIndexPtr()[e - 1], constrained.innerIndexPtr()[e]);
}

TEST(NormalEquations, TheNormalMatrixIsTheLowerTriangleOfAtAOnAnyThreadCount) {
  const RowSparse A = random_rows(4000, 900, 7);
  const ColumnSparse free_t = ColumnSparse(A.transpose());
  const int before = thread_count();
  set_thread_count(1);
  const ColumnSparse one = normal_matrix_lower(free_t);
  for (int count : {2, 3}) {
    set_thread_count(count);
    EXPECT_TRUE(fixtures::same_sparse_bits(normal_matrix_lower(free_t), one)) << count << " threads";
  }
  set_thread_count(before);
  const ColumnSparse reference = ColumnSparse(free_t * free_t.transpose()).triangularView<Eigen::Lower>();
  EXPECT_TRUE(fixtures::same_sparse_bits(one, reference)) << "not Eigen's product, bit for bit";
}
