#include "sparse_rows.hpp"

#include "animanifold/threads.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace animanifold {

RowSparseMatrix rows_of_width(Index rows, Index columns, int width,
                              const std::function<void(Index, Index*, double*)>& fill) {
  std::vector<Index> column(static_cast<size_t>(rows) * width);
  std::vector<double> value(column.size());
  std::vector<int> kept(static_cast<size_t>(rows) + 1, 0);
#pragma omp parallel num_threads(thread_count())
  {
    std::vector<int> order(static_cast<size_t>(width));
    std::vector<Index> c(static_cast<size_t>(width));
    std::vector<double> v(static_cast<size_t>(width));
#pragma omp for schedule(static)
    for (Index r = 0; r < rows; ++r) {
      Index* row_columns = column.data() + static_cast<size_t>(r) * width;
      double* row_values = value.data() + static_cast<size_t>(r) * width;
      fill(r, c.data(), v.data());
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return c[a] < c[b]; });
      int count = 0;
      for (int e = 0; e < width; ++e) {
        const int from = order[e];
        if (count > 0 && row_columns[count - 1] == c[from]) {
          row_values[count - 1] += v[from];
        } else {
          row_columns[count] = c[from];
          row_values[count++] = v[from];
        }
      }
      kept[r + 1] = count;
    }
  }
  std::partial_sum(kept.begin(), kept.end(), kept.begin());
  RowSparseMatrix M(rows, columns);
  M.resizeNonZeros(kept.back());
  std::copy(kept.begin(), kept.end(), M.outerIndexPtr());
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index r = 0; r < rows; ++r) {
    const size_t from = static_cast<size_t>(r) * width;
    std::copy(column.begin() + from, column.begin() + from + (kept[r + 1] - kept[r]), M.innerIndexPtr() + kept[r]);
    std::copy(value.begin() + from, value.begin() + from + (kept[r + 1] - kept[r]), M.valuePtr() + kept[r]);
  }
  return M;
}

RowSparseMatrix product_by_row_blocks(const RowSparseMatrix& A, const RowSparseMatrix& B) {
  const Index rows = static_cast<Index>(A.rows());
  // Several blocks a thread, so that one with the heavier rows does not hold the others.
  const Index blocks = std::max<Index>(1, std::min<Index>(4 * thread_count(), rows));
  std::vector<RowSparseMatrix> parts(static_cast<size_t>(blocks));
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
  for (Index b = 0; b < blocks; ++b) {
    const Index first = rows * b / blocks, last = rows * (b + 1) / blocks;
    parts[b] = A.middleRows(first, last - first) * B;
  }
  Eigen::Index entries = 0;
  for (const RowSparseMatrix& part : parts) entries += part.nonZeros();
  RowSparseMatrix M(rows, B.cols());
  M.resizeNonZeros(entries);
  Eigen::Index at = 0;
  for (Index b = 0; b < blocks; ++b) {
    const RowSparseMatrix& part = parts[b];
    const Index first = rows * b / blocks;
    for (Index r = 0; r < part.rows(); ++r) M.outerIndexPtr()[first + r] = static_cast<int>(at + part.outerIndexPtr()[r]);
    std::copy(part.innerIndexPtr(), part.innerIndexPtr() + part.nonZeros(), M.innerIndexPtr() + at);
    std::copy(part.valuePtr(), part.valuePtr() + part.nonZeros(), M.valuePtr() + at);
    at += part.nonZeros();
  }
  M.outerIndexPtr()[rows] = static_cast<int>(at);
  return M;
}

}  // namespace animanifold
