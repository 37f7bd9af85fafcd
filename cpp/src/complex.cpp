#include "animanifold/complex.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"
#include "animanifold/validation.hpp"

#include <Eigen/Dense>
#include <omp.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

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

// Orders the records of one bucket (equal smallest vertex, key[0]) by the
// rest of their keys: unrolled, it is much cheaper than std::array's
// three-way comparison, and the buckets' sorts are most of the work.
bool by_later_vertices(const FacetRecord& x, const FacetRecord& y) {
  if (x.key[1] != y.key[1]) return x.key[1] < y.key[1];
  if (x.key[2] != y.key[2]) return x.key[2] < y.key[2];
  return x.key[3] < y.key[3];
}

// Every facet's record, sorted by key, in buckets: records with equal keys
// share a bucket, and `start` holds each bucket's first record (and the
// count last).
struct SortedFacets {
  std::unique_ptr<FacetRecord[]> records;  // default-initialised: filled below, never zeroed
  std::vector<size_t> start;
  size_t size() const { return start.back(); }
};

// One comparison sort of all records, for indices spread far wider than the
// records (a few simplices of a large mesh): one bucket.
SortedFacets sorted_in_one_bucket(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  const size_t count = static_cast<size_t>(S.rows()) * k;
  SortedFacets out{std::unique_ptr<FacetRecord[]>(new FacetRecord[count]), {0, count}};
  for (Index s = 0; s < S.rows(); ++s)
    for (int i = 0; i < k; ++i) out.records[static_cast<size_t>(s) * k + i] = facet_record(S, s, i);
  std::sort(out.records.get(), out.records.get() + count, [](const FacetRecord& a, const FacetRecord& b) { return a.key < b.key; });
  return out;
}

// A comparison sort of all records (tens of millions for a morph's manifold)
// is slow and serial; instead each thread counts, then places, the records
// of its run of simplices into buckets by their smallest vertex (a counting
// sort, which keeps simplex order: a bucket holds the first thread's records,
// then the second's), and the buckets, a few dozen records each, are sorted
// by key on all threads. The buckets and their contents do not depend on the
// thread count, so neither does the result. Indices spread far wider than
// the records fall back to one sort, which needs no counter per index.
SortedFacets sorted_facet_records(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  if (k < 2 || k > 5) fail<InputError>("simplices with ", k, " vertices are not supported (2..5)");
  const size_t count = static_cast<size_t>(S.rows()) * k;
  const Index lowest = S.size() ? S.minCoeff() : 0, highest = S.size() ? S.maxCoeff() : 0;
  const double spread = static_cast<double>(highest) - static_cast<double>(lowest) + 1;
  if (spread > 2.0 * static_cast<double>(count) + 1024) return sorted_in_one_bucket(S);
  const size_t buckets = static_cast<size_t>(spread);
  const int most = thread_count();
  // counts[t * buckets + b]: thread t's records in bucket b; then where they
  // go. 32 bits: the counters are hit at random, and half the bytes keep
  // more of them in cache.
  if (count >= std::numeric_limits<std::uint32_t>::max()) fail<InputError>("too many facets to sort: ", count);
  std::vector<std::uint32_t> counts(static_cast<size_t>(most) * buckets, 0);
  SortedFacets out{std::unique_ptr<FacetRecord[]>(new FacetRecord[count]), std::vector<size_t>(buckets + 1, 0)};
  auto bucket_of = [&](Index s, int i) { return static_cast<size_t>(smallest_facet_vertex(S, s, i) - lowest); };
#pragma omp parallel num_threads(most)
  {
    const Index team = omp_get_num_threads(), me = omp_get_thread_num();
    const Index first = S.rows() * me / team, last = S.rows() * (me + 1) / team;
    std::uint32_t* mine = counts.data() + static_cast<size_t>(me) * buckets;
    for (Index s = first; s < last; ++s)
      for (int i = 0; i < k; ++i) ++mine[bucket_of(s, i)];
#pragma omp barrier
#pragma omp single
    {
      size_t at = 0;
      for (size_t b = 0; b < buckets; ++b) {
        out.start[b] = at;
        for (Index t = 0; t < team; ++t) {
          const size_t here = counts[static_cast<size_t>(t) * buckets + b];
          counts[static_cast<size_t>(t) * buckets + b] = static_cast<std::uint32_t>(at);
          at += here;
        }
      }
      out.start[buckets] = at;
    }
    for (Index s = first; s < last; ++s)
      for (int i = 0; i < k; ++i) out.records[mine[bucket_of(s, i)]++] = facet_record(S, s, i);
#pragma omp barrier
#pragma omp for schedule(static, 4096)
    for (size_t b = 0; b < buckets; ++b)
      std::sort(out.records.get() + out.start[b], out.records.get() + out.start[b + 1],
                by_later_vertices);
  }
  return out;
}

// Calls visit(thread, first, last) for each run of records with equal keys,
// on all threads: each thread takes the runs of a range of buckets, in
// order; `thread` numbers the ranges (0 .. thread_count() - 1).
template <class Visit>
void for_each_facet_group(const SortedFacets& sorted, Visit visit) {
  const FacetRecord* records = sorted.records.get();
  const size_t buckets = sorted.start.size() - 1;
  const int ranges = thread_count();
#pragma omp parallel for schedule(static, 1) num_threads(ranges)
  for (int range = 0; range < ranges; ++range) {
    size_t begin = sorted.start[buckets * static_cast<size_t>(range) / ranges];
    const size_t end_of_range = sorted.start[buckets * (static_cast<size_t>(range) + 1) / ranges];
    while (begin < end_of_range) {
      size_t end = begin + 1;
      while (end < end_of_range && records[end].key == records[begin].key) ++end;
      visit(range, begin, end);
      begin = end;
    }
  }
}

bool has_repeated_vertex(const Index* s, int k) {
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      if (s[a] == s[b]) return true;
  return false;
}

// The facets in exactly one simplex, in simplex order, oriented as facets of
// their simplex.
SimplexMatrix boundary_of(const SimplexMatrix& S, const SortedFacets& sorted) {
  const int k = static_cast<int>(S.cols());
  std::vector<std::vector<std::pair<Index, int>>> found(static_cast<size_t>(thread_count()));
  for_each_facet_group(sorted, [&](int range, size_t begin, size_t end) {
    if (end - begin == 1) found[range].emplace_back(sorted.records[begin].simplex, sorted.records[begin].index);
  });
  std::vector<std::pair<Index, int>> boundary;
  for (const auto& part : found) boundary.insert(boundary.end(), part.begin(), part.end());
  std::sort(boundary.begin(), boundary.end());
  SimplexMatrix B(static_cast<Index>(boundary.size()), k - 1);
  for (size_t r = 0; r < boundary.size(); ++r)
    facet(S.row(boundary[r].first).data(), k, boundary[r].second, B.row(static_cast<Index>(r)).data());
  return B;
}

}  // namespace

FacetAdjacency facet_adjacency(const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  FacetAdjacency adjacency;
  adjacency.neighbour = SimplexMatrix::Constant(S.rows(), k, -1);
  adjacency.opposite = SimplexMatrix::Constant(S.rows(), k, -1);
  const SortedFacets sorted = sorted_facet_records(S);
  const FacetRecord* records = sorted.records.get();
  // Per range, the first facet in more than two simplices: the first of all
  // is reported, the same on any thread count.
  std::vector<std::pair<size_t, size_t>> crowded(static_cast<size_t>(thread_count()), {SIZE_MAX, 0});
  for_each_facet_group(sorted, [&](int range, size_t begin, size_t end) {
    if (end - begin > 2 && crowded[range].first == SIZE_MAX) crowded[range] = {begin, end - begin};
    if (end - begin == 2) {
      const auto& a = records[begin];
      const auto& b = records[begin + 1];
      adjacency.neighbour(a.simplex, a.index) = b.simplex;
      adjacency.opposite(a.simplex, a.index) = b.index;
      adjacency.neighbour(b.simplex, b.index) = a.simplex;
      adjacency.opposite(b.simplex, b.index) = a.index;
    }
  });
  const auto first = *std::min_element(crowded.begin(), crowded.end());
  if (first.first != SIZE_MAX) {
    const auto& r = records[first.first];
    fail<InputError>("facet (", r.key[0], ", ", r.key[1], k > 3 ? ", ..." : "", ") of simplex ", r.simplex,
                     " is shared by ", first.second, " simplices: the complex is not a manifold");
  }
  return adjacency;
}

SimplexMatrix boundary_facets(const SimplexMatrix& S) { return boundary_of(S, sorted_facet_records(S)); }

ManifoldReport check_manifold(const SimplexMatrix& S, SimplexMatrix* boundary) {
  ManifoldReport report;
  const int k = static_cast<int>(S.cols());
  std::int64_t degenerate = 0;
#pragma omp parallel for schedule(static) reduction(+ : degenerate) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) degenerate += has_repeated_vertex(S.row(s).data(), k);
  report.degenerate_simplices = degenerate;
  const SortedFacets sorted = sorted_facet_records(S);
  std::vector<ManifoldReport> part(static_cast<size_t>(thread_count()));
  for_each_facet_group(sorted, [&](int range, size_t begin, size_t end) {
    ManifoldReport& r = part[range];
    const size_t count = end - begin;
    if (count == 1) ++r.boundary_facets;
    else if (count > 2) ++r.nonmanifold_facets;
    else {
      ++r.interior_facets;
      if (sorted.records[begin].parity == sorted.records[begin + 1].parity) ++r.misoriented_facets;
    }
  });
  for (const ManifoldReport& r : part) {
    report.boundary_facets += r.boundary_facets, report.nonmanifold_facets += r.nonmanifold_facets;
    report.interior_facets += r.interior_facets, report.misoriented_facets += r.misoriented_facets;
  }
  if (boundary) *boundary = boundary_of(S, sorted);
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
