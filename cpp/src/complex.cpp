#include "animanifold/complex.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"
#include "animanifold/validation.hpp"

#include <Eigen/Dense>
#include <omp.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace animanifold {

void Complex::validate() const {
  const Index n = static_cast<Index>(V.rows());
  for (Index v = 0; v < n; ++v)
    for (int c = 0; c < V.cols(); ++c)
      if (!std::isfinite(V(v, c))) fail<InputError>("vertex ", v, " has a non-finite coordinate ", c);
  // Slicing divides by differences of coordinates: each must be finite too.
  for (int c = 0; c < V.cols() && n > 0; ++c) {
    const double low = V.col(c).minCoeff(), high = V.col(c).maxCoeff();
    if (!std::isfinite(high - low))
      fail<InputError>("vertex coordinates ", c, " span from ", low, " to ", high, ", more than a double can hold");
  }
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < S.cols(); ++c)
      if (S(s, c) < 0 || S(s, c) >= n)
        fail<InputError>("simplex ", s, " refers to vertex ", S(s, c), ", outside 0..", n - 1);
  for (const auto& [name, table] : vertex_attributes)
    if (table.rows() != V.rows())
      fail<InputError>("vertex attribute '", name, "' has ", table.rows(), " rows for ", V.rows(), " vertices");
  for (const auto& [name, table] : simplex_attributes)
    if (table.rows() != S.rows())
      fail<InputError>("simplex attribute '", name, "' has ", table.rows(), " rows for ", S.rows(), " simplices");
}

SimplexMatrix facets(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  SimplexMatrix F(S.rows() * k, k - 1);
  for (Index s = 0; s < S.rows(); ++s)
    for (int i = 0; i < k; ++i) facet(S.row(s).data(), k, i, F.row(s * k + i).data());
  return F;
}

namespace {

// One facet occurrence, sortable by its vertex set. Facets have at most four
// vertices (simplices of at most five: 4-simplices filling R^4).
struct FacetRecord {
  std::array<Index, 4> key;
  Index simplex;
  std::int8_t index;
  std::int8_t parity;
};

FacetRecord facet_record(const SimplexMatrix& S, Index s, int i) {
  const int k = static_cast<int>(S.cols());
  Index f[5];
  facet(S.row(s).data(), k, i, f);
  FacetRecord r;
  r.key.fill(-1);
  std::copy(f, f + k - 1, r.key.begin());
  // A vertex facet of an edge carries its orientation as a sign: the rule's
  // "swap" of facet i+1 even (the edge's start) has nothing to swap, so it
  // negates instead (the end of an edge is +, its start is -).
  r.parity = static_cast<std::int8_t>(k == 2 ? (i % 2 == 0 ? 1 : -1) : permutation_parity(f, k - 1));
  std::sort(r.key.begin(), r.key.begin() + (k - 1));
  r.simplex = s;
  r.index = static_cast<std::int8_t>(i);
  return r;
}

// The smallest vertex of facet i of simplex s (its key's first entry).
Index smallest_facet_vertex(const SimplexMatrix& S, Index s, int i) {
  Index smallest = std::numeric_limits<Index>::max();
  for (int c = 0; c < S.cols(); ++c)
    if (c != i) smallest = std::min(smallest, S(s, c));
  return smallest;
}

// Every facet's record, sorted by key. A comparison sort of all records
// (tens of millions for a morph's manifold) is slow and serial; instead the
// records are placed in buckets by their smallest vertex (a counting sort,
// which keeps simplex order) and each bucket, a few dozen records, is sorted
// by key on all threads. The buckets and their contents do not depend on the
// thread count, so neither does the result. Indices spread far wider than
// the records (a few simplices of a large mesh) fall back to one sort, which
// needs no counter per index.
std::vector<FacetRecord> sorted_facet_records(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  if (k < 2 || k > 5) fail<InputError>("simplices with ", k, " vertices are not supported (2..5)");
  const size_t count = static_cast<size_t>(S.rows()) * k;
  const auto by_key = [](const FacetRecord& a, const FacetRecord& b) { return a.key < b.key; };
  std::vector<FacetRecord> records(count);
  const Index lowest = S.size() ? S.minCoeff() : 0, highest = S.size() ? S.maxCoeff() : 0;
  const double spread = static_cast<double>(highest) - static_cast<double>(lowest) + 1;
  if (spread > 2.0 * static_cast<double>(count) + 1024) {
    for (Index s = 0; s < S.rows(); ++s)
      for (int i = 0; i < k; ++i) records[static_cast<size_t>(s) * k + i] = facet_record(S, s, i);
    std::sort(records.begin(), records.end(), by_key);
    return records;
  }
  const size_t buckets = static_cast<size_t>(spread);
  std::vector<size_t> start(buckets + 1, 0);
  for (Index s = 0; s < S.rows(); ++s)
    for (int i = 0; i < k; ++i) ++start[static_cast<size_t>(smallest_facet_vertex(S, s, i) - lowest) + 1];
  for (size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<size_t> next(start.begin(), start.end() - 1);
#pragma omp parallel num_threads(thread_count())
  {
    // Each thread owns a run of buckets holding about its share of the
    // records, and scans every simplex for the facets that go there.
    const size_t team = static_cast<size_t>(omp_get_num_threads()), me = static_cast<size_t>(omp_get_thread_num());
    const auto first_bucket = [&](size_t part) {
      return static_cast<size_t>(std::lower_bound(start.begin(), start.end(), count * part / team) - start.begin());
    };
    const size_t low = me == 0 ? 0 : first_bucket(me), high = me + 1 == team ? buckets : first_bucket(me + 1);
    for (Index s = 0; s < S.rows(); ++s)
      for (int i = 0; i < k; ++i) {
        const size_t bucket = static_cast<size_t>(smallest_facet_vertex(S, s, i) - lowest);
        if (bucket >= low && bucket < high) records[next[bucket]++] = facet_record(S, s, i);
      }
    for (size_t b = low; b < high; ++b)
      std::sort(records.begin() + static_cast<std::ptrdiff_t>(start[b]),
                records.begin() + static_cast<std::ptrdiff_t>(start[b + 1]), by_key);
  }
  return records;
}

// Calls visit(first, last) for each run of records with equal keys.
template <class Visit>
void for_each_facet_group(const std::vector<FacetRecord>& records, Visit visit) {
  size_t begin = 0;
  while (begin < records.size()) {
    size_t end = begin + 1;
    while (end < records.size() && records[end].key == records[begin].key) ++end;
    visit(begin, end);
    begin = end;
  }
}

bool has_repeated_vertex(const Index* s, int k) {
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      if (s[a] == s[b]) return true;
  return false;
}

}  // namespace

FacetAdjacency facet_adjacency(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  FacetAdjacency adjacency;
  adjacency.neighbour = SimplexMatrix::Constant(S.rows(), k, -1);
  adjacency.opposite = SimplexMatrix::Constant(S.rows(), k, -1);
  const auto records = sorted_facet_records(S);
  for_each_facet_group(records, [&](size_t begin, size_t end) {
    if (end - begin > 2) {
      const auto& r = records[begin];
      fail<InputError>("facet (", r.key[0], ", ", r.key[1], k > 3 ? ", ..." : "", ") of simplex ", r.simplex,
                       " is shared by ", end - begin, " simplices: the complex is not a manifold");
    }
    if (end - begin == 2) {
      const auto& a = records[begin];
      const auto& b = records[begin + 1];
      adjacency.neighbour(a.simplex, a.index) = b.simplex;
      adjacency.opposite(a.simplex, a.index) = b.index;
      adjacency.neighbour(b.simplex, b.index) = a.simplex;
      adjacency.opposite(b.simplex, b.index) = a.index;
    }
  });
  return adjacency;
}

SimplexMatrix boundary_facets(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  const auto records = sorted_facet_records(S);
  std::vector<std::pair<Index, int>> boundary;
  for_each_facet_group(records, [&](size_t begin, size_t end) {
    if (end - begin == 1) boundary.emplace_back(records[begin].simplex, records[begin].index);
  });
  std::sort(boundary.begin(), boundary.end());
  SimplexMatrix B(static_cast<Index>(boundary.size()), k - 1);
  for (size_t r = 0; r < boundary.size(); ++r)
    facet(S.row(boundary[r].first).data(), k, boundary[r].second, B.row(static_cast<Index>(r)).data());
  return B;
}

ManifoldReport check_manifold(const SimplexMatrix& S) {
  ManifoldReport report;
  const int k = static_cast<int>(S.cols());
  for (Index s = 0; s < S.rows(); ++s)
    if (has_repeated_vertex(S.row(s).data(), k)) ++report.degenerate_simplices;
  const auto records = sorted_facet_records(S);
  for_each_facet_group(records, [&](size_t begin, size_t end) {
    const size_t count = end - begin;
    if (count == 1) ++report.boundary_facets;
    else if (count > 2) ++report.nonmanifold_facets;
    else {
      ++report.interior_facets;
      if (records[begin].parity == records[begin + 1].parity) ++report.misoriented_facets;
    }
  });
  return report;
}

Eigen::VectorXd signed_volumes(const PointMatrix& V, const SimplexMatrix& S) {
  const int D = static_cast<int>(V.cols());
  if (S.cols() != D + 1)
    fail<InputError>("signed volume needs full-dimensional simplices: ", S.cols(), " vertices in R^", D);
  check_indices(S, V.rows(), "simplex");
  double factorial = 1;
  for (int i = 2; i <= D; ++i) factorial *= i;
  Eigen::VectorXd volumes(S.rows());
  // Each simplex writes its own entry: the same volumes for any thread count.
#pragma omp parallel num_threads(thread_count())
  {
    Eigen::MatrixXd edges(D, D);
#pragma omp for schedule(static)
    for (Index s = 0; s < S.rows(); ++s) {
      for (int i = 0; i < D; ++i) edges.row(i) = V.row(S(s, i + 1)) - V.row(S(s, 0));
      volumes(s) = edges.determinant() / factorial;
    }
  }
  return volumes;
}

double relative_volume(const PointMatrix& V, const Index* corners) {
  const int D = static_cast<int>(V.cols());
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4> edges(D, D);
  double longest = 0;
  for (int i = 0; i < D; ++i) edges.row(i) = V.row(corners[i + 1]) - V.row(corners[0]);
  for (int a = 0; a <= D; ++a)
    for (int b = a + 1; b <= D; ++b) longest = std::max(longest, (V.row(corners[a]) - V.row(corners[b])).squaredNorm());
  return longest > 0 ? std::abs(edges.determinant()) / std::pow(longest, 0.5 * D) : 0.0;
}

Eigen::VectorXd simplex_volumes(const PointMatrix& V, const SimplexMatrix& S) {
  check_indices(S, V.rows(), "simplex");
  const int n = static_cast<int>(S.cols()) - 1;
  double factorial = 1;
  for (int i = 2; i <= n; ++i) factorial *= i;
  Eigen::VectorXd volumes(S.rows());
  Eigen::MatrixXd edges(n, V.cols());
  for (Index s = 0; s < S.rows(); ++s) {
    for (int i = 0; i < n; ++i) edges.row(i) = V.row(S(s, i + 1)) - V.row(S(s, 0));
    const double gram = (edges * edges.transpose()).determinant();
    volumes(s) = std::sqrt(std::max(gram, 0.0)) / factorial;
  }
  return volumes;
}

VertexStar vertex_star(const SimplexMatrix& S, Index vertex_count) {
  check_indices(S, vertex_count, "simplex");
  VertexStar star;
  star.offsets.assign(static_cast<size_t>(vertex_count) + 1, 0);
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < S.cols(); ++c) ++star.offsets[S(s, c) + 1];
  for (Index v = 0; v < vertex_count; ++v) star.offsets[v + 1] += star.offsets[v];
  star.simplices.resize(star.offsets.back());
  std::vector<Index> cursor(star.offsets.begin(), star.offsets.end() - 1);
  for (Index s = 0; s < S.rows(); ++s)
    for (int c = 0; c < S.cols(); ++c) star.simplices[cursor[S(s, c)]++] = s;
  return star;
}

}  // namespace animanifold
