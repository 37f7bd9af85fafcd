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

// A simplex's vertices in ascending order, where each came from, and the
// parity of the sort: facet j of the sorted simplex (without its j-th
// smallest vertex) is then already sorted, and the orientation the simplex
// induces on it (§2.4's facet rule, relative to that order) is
// parity * (-1)^j. One sort per simplex instead of one per facet.
struct SortedSimplex {
  Index vertex[5];
  std::int8_t origin[5];
  int parity = 1;
};
SortedSimplex sorted_simplex(const SimplexMatrix& S, Index s) {
  const int k = static_cast<int>(S.cols());
  SortedSimplex out;
  for (int c = 0; c < k; ++c) {  // insertion sort: each step past a larger vertex is one inversion
    Index v = S(s, c);
    int at = c;
    for (; at > 0 && out.vertex[at - 1] > v; --at) {
      out.vertex[at] = out.vertex[at - 1], out.origin[at] = out.origin[at - 1];
      out.parity = -out.parity;
    }
    out.vertex[at] = v, out.origin[at] = static_cast<std::int8_t>(c);
  }
  return out;
}

// The record of facet j of the sorted simplex s (`k` vertices).
FacetRecord facet_record(const SortedSimplex& sorted, Index s, int k, int j) {
  FacetRecord r;
  r.key.fill(-1);
  for (int c = 0, at = 0; c < k; ++c)  // k <= 5, checked by the callers
    if (c != j) r.key[at++] = sorted.vertex[c];
  r.parity = static_cast<std::int8_t>(j % 2 == 0 ? sorted.parity : -sorted.parity);
  r.simplex = s;
  r.index = sorted.origin[j];
  return r;
}

// Orders records by key. Within one bucket (equal smallest vertex, key[0])
// only the rest differ; unrolled, this is much cheaper than std::array's
// three-way comparison, and the buckets' sorts are much of the work.
bool by_key(const FacetRecord& x, const FacetRecord& y) {
  if (x.key[0] != y.key[0]) return x.key[0] < y.key[0];
  // key[1] and key[2] as one unsigned number (-1, unused, compares last):
  // one comparison where two would branch.
  auto middle = [](const FacetRecord& r) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(r.key[1])) << 32) |
           static_cast<std::uint32_t>(r.key[2]);
  };
  const std::uint64_t a = middle(x), b = middle(y);
  return a != b ? a < b : x.key[3] < y.key[3];
}

// Sorts one bucket's records (all with one smallest vertex, key[0]) by key.
// Where the rest of a key is at most two vertices (facets of triangles or
// tets) below 2^27 and the bucket has fewer than 1024 records, each record
// is sorted as one 64-bit number, (key[1] + 1, key[2] + 1, its place in the
// bucket) from the high bits down, and the records then put in that order:
// a sort of numbers instead of 24-byte records (the buckets' sorts were
// about half of a manifold check's time).
class BucketSorter {
 public:
  static constexpr int kPlaceBits = 10, kVertexBits = 27;
  // Inputs: k vertices a simplex; lowest, highest: the least and largest vertex index
  BucketSorter(int k, Index lowest, Index highest)
      : packed_(k <= 4 && lowest >= 0 && highest < (Index{1} << kVertexBits) - 1) {}

  void sort(std::vector<FacetRecord>& bucket) {
    if (!packed_ || bucket.size() >= (size_t{1} << kPlaceBits)) {
      std::sort(bucket.begin(), bucket.end(), by_key);
      return;
    }
    numbers_.resize(bucket.size());
    for (size_t i = 0; i < bucket.size(); ++i) {
      const FacetRecord& r = bucket[i];
      numbers_[i] = static_cast<std::uint64_t>(r.key[1] + 1) << (kVertexBits + kPlaceBits) |
                    static_cast<std::uint64_t>(r.key[2] + 1) << kPlaceBits | i;
    }
    std::sort(numbers_.begin(), numbers_.end());
    sorted_.resize(bucket.size());
    for (size_t i = 0; i < bucket.size(); ++i) sorted_[i] = bucket[numbers_[i] & ((1u << kPlaceBits) - 1)];
    bucket.swap(sorted_);
  }

 private:
  bool packed_;
  std::vector<std::uint64_t> numbers_;
  std::vector<FacetRecord> sorted_;
};

// Calls visit(range, group, count) for each run of `count` records with
// equal keys, `group` its first, in key order within each range.
template <class Visit>
void visit_groups(int range, const std::vector<FacetRecord>& sorted, Visit& visit) {
  size_t begin = 0;
  while (begin < sorted.size()) {
    size_t end = begin + 1;
    while (end < sorted.size() && sorted[end].key == sorted[begin].key) ++end;
    visit(range, sorted.data() + begin, end - begin);
    begin = end;
  }
}

// Simplex s's smallest vertex and the smallest of the others: every facet's
// smallest vertex is the first but the one facet without it, whose is the
// second.
struct SmallestTwo {
  Index first, second;
};
SmallestTwo smallest_two(const SimplexMatrix& S, Index s) {
  SmallestTwo out{S(s, 0), std::numeric_limits<Index>::max()};
  for (int c = 1; c < S.cols(); ++c) {
    const Index v = S(s, c);
    if (v < out.first) out.second = out.first, out.first = v;
    else out.second = std::min(out.second, v);
  }
  return out;
}

// The simplices by a vertex (CSR): `start[b]..start[b+1]` of `simplices`
// are those whose chosen vertex is lowest + b, in ascending order.
struct SimplicesBy {
  std::vector<Index> start, simplices;
};
template <class Choose>
SimplicesBy simplices_by(const SimplexMatrix& S, Index lowest, size_t buckets, Choose choose) {
  SimplicesBy out{std::vector<Index>(buckets + 1, 0), std::vector<Index>(S.rows())};
  for (Index s = 0; s < S.rows(); ++s) ++out.start[choose(s) - lowest + 1];
  for (size_t b = 0; b < buckets; ++b) out.start[b + 1] += out.start[b];
  std::vector<Index> next(out.start.begin(), out.start.end() - 1);
  for (Index s = 0; s < S.rows(); ++s) out.simplices[next[choose(s) - lowest]++] = s;
  return out;
}

// Calls visit(range, group, count) for every facet shared by `count`
// simplices (a run of records with one key; `group` points at the first),
// on all threads: the facets are taken in buckets by their smallest vertex,
// each bucket's few dozen records made and sorted where they are used, so
// no table of every facet's record is ever written. The buckets are split
// into `ranges` runs (0 .. ranges - 1, the caller's slots for what it
// gathers: the caller's count, so a thread setting changed meanwhile cannot
// overrun them), each taken in order by one thread; what the caller sums or
// sorts from the ranges is then the same on any thread count. Indices spread
// far wider than the simplices (a few simplices of a large mesh) are taken
// as one bucket, sorted whole: range 0 then visits every facet.
template <class Visit>
void for_each_facet_group(const SimplexMatrix& S, int ranges, Visit visit) {
  const int k = static_cast<int>(S.cols());
  if (k < 2 || k > 5) fail<InputError>("simplices with ", k, " vertices are not supported (2..5)");
  if (S.rows() == 0) return;
  const Index lowest = S.minCoeff(), highest = S.maxCoeff();
  const double spread = static_cast<double>(highest) - static_cast<double>(lowest) + 1;
  if (spread > 2.0 * static_cast<double>(S.rows()) * k + 1024) {
    std::vector<FacetRecord> all;
    all.reserve(static_cast<size_t>(S.rows()) * k);
    for (Index s = 0; s < S.rows(); ++s) {
      const SortedSimplex sorted = sorted_simplex(S, s);
      for (int j = 0; j < k; ++j) all.push_back(facet_record(sorted, s, k, j));
    }
    std::sort(all.begin(), all.end(), by_key);
    visit_groups(0, all, visit);
    return;
  }
  const size_t buckets = static_cast<size_t>(spread);
  // Facets whose smallest vertex is a simplex's smallest, and the one facet
  // (without it) whose smallest is the simplex's second smallest. Each
  // simplex's two are found once: the passes that bucket by them read them.
  std::vector<SmallestTwo> smallest(static_cast<size_t>(S.rows()));
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) smallest[s] = smallest_two(S, s);
  const SimplicesBy by_first = simplices_by(S, lowest, buckets, [&](Index s) { return smallest[s].first; });
  const SimplicesBy by_second = simplices_by(S, lowest, buckets, [&](Index s) { return smallest[s].second; });
#pragma omp parallel for schedule(static, 1) num_threads(std::min(ranges, thread_count()))
  for (int range = 0; range < ranges; ++range) {
    std::vector<FacetRecord> bucket;
    BucketSorter sorter(k, lowest, highest);
    const size_t first = buckets * static_cast<size_t>(range) / ranges;
    const size_t last = buckets * (static_cast<size_t>(range) + 1) / ranges;
    // The simplices of the buckets ahead, read at random, are fetched early:
    // this loop waits on memory more than it computes.
    constexpr Index kAhead = 16;
    auto fetch_ahead = [&](const SimplicesBy& by, Index at) {
      if (at + kAhead < static_cast<Index>(by.simplices.size())) __builtin_prefetch(S.row(by.simplices[at + kAhead]).data());
    };
    for (size_t b = first; b < last; ++b) {
      bucket.clear();
      for (Index at = by_first.start[b]; at < by_first.start[b + 1]; ++at) {
        fetch_ahead(by_first, at);
        const Index s = by_first.simplices[at];
        const SortedSimplex sorted = sorted_simplex(S, s);
        for (int j = 1; j < k; ++j) bucket.push_back(facet_record(sorted, s, k, j));
      }
      for (Index at = by_second.start[b]; at < by_second.start[b + 1]; ++at) {
        fetch_ahead(by_second, at);
        const Index s = by_second.simplices[at];
        bucket.push_back(facet_record(sorted_simplex(S, s), s, k, 0));
      }
      sorter.sort(bucket);
      visit_groups(range, bucket, visit);
    }
  }
}

bool has_repeated_vertex(const Index* s, int k) {
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      if (s[a] == s[b]) return true;
  return false;
}

// Facets in exactly one simplex (the boundary) as (simplex, facet), in
// simplex order, written as facets of their simplex.
SimplexMatrix as_facets(const SimplexMatrix& S, std::vector<std::vector<std::pair<Index, int>>>& found) {
  const int k = static_cast<int>(S.cols());
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
  // Per range, the first facet in more than two simplices: the one with the
  // smallest key of all is reported, the same on any thread count.
  std::vector<std::pair<FacetRecord, size_t>> crowded(static_cast<size_t>(thread_count()), {FacetRecord{}, 0});
  for_each_facet_group(S, static_cast<int>(crowded.size()), [&](int range, const FacetRecord* group, size_t count) {
    if (count > 2 && crowded[range].second == 0) crowded[range] = {group[0], count};
    if (count == 2) {
      const FacetRecord &a = group[0], &b = group[1];
      adjacency.neighbour(a.simplex, a.index) = b.simplex;
      adjacency.opposite(a.simplex, a.index) = b.index;
      adjacency.neighbour(b.simplex, b.index) = a.simplex;
      adjacency.opposite(b.simplex, b.index) = a.index;
    }
  });
  const std::pair<FacetRecord, size_t>* first = nullptr;
  for (const auto& c : crowded)
    if (c.second && (!first || by_key(c.first, first->first))) first = &c;
  if (first) {
    const FacetRecord& r = first->first;
    fail<InputError>("facet (", r.key[0], ", ", r.key[1], k > 3 ? ", ..." : "", ") of simplex ", r.simplex,
                     " is shared by ", first->second, " simplices: the complex is not a manifold");
  }
  return adjacency;
}

SimplexMatrix boundary_facets(const SimplexMatrix& S) {
  SimplexMatrix B;
  check_manifold(S, &B);
  return B;
}

ManifoldReport check_manifold(const SimplexMatrix& S, SimplexMatrix* boundary) {
  ManifoldReport report;
  const int k = static_cast<int>(S.cols());
  std::int64_t degenerate = 0;
#pragma omp parallel for schedule(static) reduction(+ : degenerate) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) degenerate += has_repeated_vertex(S.row(s).data(), k);
  report.degenerate_simplices = degenerate;
  std::vector<ManifoldReport> part(static_cast<size_t>(thread_count()));
  std::vector<std::vector<std::pair<Index, int>>> found(part.size());
  for_each_facet_group(S, static_cast<int>(part.size()), [&](int range, const FacetRecord* group, size_t count) {
    ManifoldReport& r = part[range];
    if (count == 1) {
      ++r.boundary_facets;
      if (boundary) found[range].emplace_back(group[0].simplex, group[0].index);
    } else if (count > 2) {
      ++r.nonmanifold_facets;
    } else {
      ++r.interior_facets;
      if (group[0].parity == group[1].parity) ++r.misoriented_facets;
    }
  });
  for (const ManifoldReport& r : part) {
    report.boundary_facets += r.boundary_facets, report.nonmanifold_facets += r.nonmanifold_facets;
    report.interior_facets += r.interior_facets, report.misoriented_facets += r.misoriented_facets;
  }
  if (boundary) *boundary = as_facets(S, found);
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
