#include "normal_equations.hpp"

#include "animanifold/threads.hpp"

#include <algorithm>
#include <utility>

namespace animanifold {

void split_columns(const RowSparse& A, const std::vector<Index>& column, Index free_count, Index constraint_count,
                   ColumnSparse& free_t, RowSparse& constrained) {
  const Index rows = static_cast<Index>(A.rows());
  std::vector<int> free_starts(rows + 1, 0), fixed_starts(rows + 1, 0);
  for (Index r = 0; r < rows; ++r) {
    int free_entries = 0, fixed_entries = 0;
    for (RowSparse::InnerIterator it(A, r); it; ++it) (column[it.col()] >= 0 ? free_entries : fixed_entries)++;
    free_starts[r + 1] = free_starts[r] + free_entries;
    fixed_starts[r + 1] = fixed_starts[r] + fixed_entries;
  }
  // Both outputs are filled in place: one compressed column (row) per row of A.
  free_t.resize(free_count, rows);
  free_t.resizeNonZeros(free_starts[rows]);
  constrained.resize(rows, constraint_count);
  constrained.resizeNonZeros(fixed_starts[rows]);
  std::copy(free_starts.begin(), free_starts.end(), free_t.outerIndexPtr());
  std::copy(fixed_starts.begin(), fixed_starts.end(), constrained.outerIndexPtr());
  std::vector<std::pair<int, double>> fixed;
  for (Index r = 0; r < rows; ++r) {
    int next = free_starts[r];
    fixed.clear();
    for (RowSparse::InnerIterator it(A, r); it; ++it) {
      const Index c = column[it.col()];
      if (c >= 0) {  // free unknowns ascend with the vertex: the column stays sorted
        free_t.innerIndexPtr()[next] = c;
        free_t.valuePtr()[next++] = it.value();
      } else {
        fixed.emplace_back(-c - 2, it.value());
      }
    }
    std::sort(fixed.begin(), fixed.end());
    for (size_t e = 0; e < fixed.size(); ++e) {
      constrained.innerIndexPtr()[fixed_starts[r] + e] = fixed[e].first;
      constrained.valuePtr()[fixed_starts[r] + e] = fixed[e].second;
    }
  }
}

namespace {

// Columns [first, first + count) of the lower triangle of free_t · free_tᵀ,
// where free = free_tᵀ (column-major: column j lists the rows of unknown j).
ColumnSparse lower_columns(const ColumnSparse& free_t, const ColumnSparse& free, Index first, Index count) {
  const ColumnSparse block = free_t * free.middleCols(first, count);
  ColumnSparse lower(block.rows(), count);
  lower.reserve(block.nonZeros() / 2 + count);
  for (Index j = 0; j < count; ++j) {
    lower.startVec(j);
    for (ColumnSparse::InnerIterator it(block, j); it; ++it)
      if (it.row() >= first + j) lower.insertBack(it.row(), j) = it.value();
  }
  lower.finalize();
  return lower;
}

// Blocks of columns of about equal work (entries of `free`, their rows),
// many per thread so that a thread with the heavy columns does not hold the others.
std::vector<Index> block_starts(const ColumnSparse& free) {
  const Index columns = static_cast<Index>(free.cols());
  const int blocks = std::max(1, std::min<int>(4 * thread_count(), static_cast<int>(columns)));
  std::vector<Index> starts{0};
  const double per_block = static_cast<double>(free.nonZeros()) / blocks;
  for (Index j = 0; j < columns; ++j)
    if (free.outerIndexPtr()[j + 1] >= per_block * static_cast<double>(starts.size()) &&
        static_cast<int>(starts.size()) < blocks)
      starts.push_back(j + 1);
  if (starts.back() != columns) starts.push_back(columns);
  return starts;
}

}  // namespace

ColumnSparse normal_matrix_lower(const ColumnSparse& free_t) {
  const ColumnSparse free = free_t.transpose();
  const std::vector<Index> starts = block_starts(free);
  const int blocks = static_cast<int>(starts.size()) - 1;
  std::vector<ColumnSparse> parts(static_cast<size_t>(blocks));
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
  for (int b = 0; b < blocks; ++b) parts[b] = lower_columns(free_t, free, starts[b], starts[b + 1] - starts[b]);
  Eigen::Index entries = 0;
  for (const ColumnSparse& part : parts) entries += part.nonZeros();
  ColumnSparse N(free_t.rows(), free_t.rows());
  N.resizeNonZeros(entries);
  Eigen::Index at = 0;
  for (int b = 0; b < blocks; ++b) {
    const ColumnSparse& part = parts[b];
    for (Index j = 0; j < part.cols(); ++j) N.outerIndexPtr()[starts[b] + j] = static_cast<int>(at + part.outerIndexPtr()[j]);
    std::copy(part.innerIndexPtr(), part.innerIndexPtr() + part.nonZeros(), N.innerIndexPtr() + at);
    std::copy(part.valuePtr(), part.valuePtr() + part.nonZeros(), N.valuePtr() + at);
    at += part.nonZeros();
  }
  N.outerIndexPtr()[N.cols()] = static_cast<int>(at);
  return N;
}

}  // namespace animanifold
