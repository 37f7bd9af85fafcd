#include "animanifold/refine.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/memory_estimates.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace animanifold {

namespace {

constexpr int kMax = kMaxRefineVertices;

// Coordinates on input may be off their unit sum by this much (rounding in the
// caller's arithmetic); they are renormalised exactly afterwards.
constexpr double kSumTolerance = 1e-6;

// A simplex as its sorted vertex ids padded with -1: the hash key under which
// pending tuples are found (§6.2).
struct Key {
  std::array<Index, kMax> v;
  bool operator==(const Key&) const = default;
};

struct KeyHash {
  size_t operator()(const Key& key) const noexcept {
    // FNV-1a over the ids, with a final mix so that neighbouring ids spread.
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (Index x : key.v) {
      h ^= static_cast<std::uint32_t>(x);
      h *= 0x100000001b3ull;
    }
    h ^= h >> 31;
    return static_cast<size_t>(h * 0x9e3779b97f4a7c15ull);
  }
};

Key make_key(const Index* ids, int n) {
  Key key;
  key.v.fill(-1);
  std::copy(ids, ids + n, key.v.begin());
  return key;
}

// A split tuple as it currently stands: its simplex (sorted ids, so the ids
// double as the hash key) and the coordinates matching them.
struct Tuple {
  std::array<Index, kMax> v{};
  std::array<double, kMax> b{};
  int n = 0;
  bool pending = false;
  // Bumped whenever its cost is recomputed, so that stale queue entries can
  // be recognised and skipped (a lazy-deletion priority queue).
  std::uint32_t version = 0;
};

struct QueueEntry {
  double cost;
  Index tuple;
  std::uint32_t version;
  // Ties go to the earlier tuple, so the order is deterministic.
  bool operator>(const QueueEntry& o) const { return cost != o.cost ? cost > o.cost : tuple > o.tuple; }
};

// The degeneracy of §6.3 for one simplex given its k corner points.
double degeneracy_of(const double* const* corners, int k, int D) {
  double sum = 0, sum_sq = 0;
  int edges = 0;
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b) {
      double sq = 0;
      for (int c = 0; c < D; ++c) {
        const double d = corners[a][c] - corners[b][c];
        sq += d * d;
      }
      sum += std::sqrt(sq);
      sum_sq += sq;
      ++edges;
    }
  if (edges < 2 || sum <= 0) return 0;
  const double mean = sum / edges;
  const double variance = std::max(sum_sq / edges - mean * mean, 0.0);
  return variance / (mean * mean);
}

class Refiner {
 public:
  Refiner(const Complex& input, const RefineOptions& options, Index tuple_count)
      : k_(static_cast<int>(input.S.cols())),
        D_(static_cast<int>(input.V.cols())),
        input_vertices_(static_cast<Index>(input.V.rows())),
        epsilon_(options.epsilon),
        order_(options.order) {
    const size_t max_vertices = static_cast<size_t>(input_vertices_) + static_cast<size_t>(tuple_count);
    points_.reserve(max_vertices * D_);
    points_.assign(input.V.data(), input.V.data() + input.V.size());
    simplices_.assign(input.S.data(), input.S.data() + input.S.size());
    parent_.resize(input.S.rows());
    for (Index s = 0; s < input.S.rows(); ++s) parent_[s] = s;
    star_.reserve(max_vertices);
    star_.resize(input_vertices_);
    // Count first so each star is allocated once at its initial size.
    std::vector<Index> degree(input_vertices_, 0);
    for (Index x : simplices_) ++degree[x];
    for (Index v = 0; v < input_vertices_; ++v) star_[v].reserve(degree[v]);
    for (size_t s = 0; s < simplices_.size() / k_; ++s)
      for (int c = 0; c < k_; ++c) star_[simplices_[s * k_ + c]].push_back(static_cast<Index>(s));

    tuples_.resize(tuple_count);
    mark_.assign(tuple_count, 0);
    new_vertex_.assign(tuple_count, -1);
    snapped_.assign(tuple_count, -1);
    pending_by_simplex_.reserve(tuple_count);
  }

  // Validates split t (row of the caller's matrices), applies the sliver
  // control and queues it.
  void add_tuple(Index t, const Index* ids, const double* coords, int columns) {
    Tuple& u = tuples_[t];
    int m = 0;
    while (m < columns && ids[m] != -1) ++m;
    if (m == 0) fail<InputError>("split ", t, " names no vertex");
    for (int c = m; c < columns; ++c)
      if (ids[c] != -1)
        fail<InputError>("split ", t, ": vertex id ", ids[c], " in column ", c,
                         " follows the -1 padding; ids must come first");
    double sum = 0;
    std::array<std::pair<Index, double>, kMax> entries;
    for (int c = 0; c < m; ++c) {
      if (ids[c] < 0 || ids[c] >= input_vertices_)
        fail<InputError>("split ", t, ": vertex ", ids[c], " is outside 0..", input_vertices_ - 1);
      if (!std::isfinite(coords[c]) || coords[c] < 0)
        fail<InputError>("split ", t, ": barycentric coordinate ", coords[c], " of vertex ", ids[c],
                         " is not a finite number >= 0");
      sum += coords[c];
      entries[c] = {ids[c], coords[c]};
    }
    if (std::abs(sum - 1) > kSumTolerance)
      fail<InputError>("split ", t, ": barycentric coordinates sum to ", sum, ", not 1");
    std::sort(entries.begin(), entries.begin() + m);
    for (int c = 1; c < m; ++c)
      if (entries[c].first == entries[c - 1].first)
        fail<InputError>("split ", t, ": vertex ", entries[c].first, " is named twice");
    u.n = m;
    for (int c = 0; c < m; ++c) {
      u.v[c] = entries[c].first;
      u.b[c] = entries[c].second / sum;
    }
    tops_containing(u.v.data(), m, scratch_tops_);
    if (scratch_tops_.empty()) {
      std::ostringstream ids_text;
      for (int c = 0; c < m; ++c) ids_text << (c ? ", " : "") << u.v[c];
      fail<InputError>("split ", t, ": vertices (", ids_text.str(), ") are not a simplex of the complex");
    }
    u.pending = true;
    if (sliver_control(t)) insert_pending(t);
  }

  void run() {
    const Index count = static_cast<Index>(tuples_.size());
    if (order_ == RefineOrder::Given) {
      for (Index t = 0; t < count; ++t)
        if (tuples_[t].pending) apply(t);
      return;
    }
    for (Index t = 0; t < count; ++t)
      if (tuples_[t].pending) push_cost(t);
    while (!queue_.empty()) {
      const QueueEntry top = queue_.top();
      queue_.pop();
      const Tuple& u = tuples_[top.tuple];
      if (!u.pending || u.version != top.version) continue;
      apply(top.tuple);
    }
  }

  Refinement result(const Complex& input) {
    Refinement r;
    const Index vertex_count = static_cast<Index>(points_.size() / D_);
    const Index simplex_count = static_cast<Index>(simplices_.size() / k_);
    r.complex.V = Eigen::Map<const PointMatrix>(points_.data(), vertex_count, D_);
    r.complex.S = Eigen::Map<const SimplexMatrix>(simplices_.data(), simplex_count, k_);
    r.parent_simplex = Eigen::Map<const IndexVector>(parent_.data(), simplex_count);
    r.new_vertex_of_split = Eigen::Map<const IndexVector>(new_vertex_.data(), static_cast<Index>(new_vertex_.size()));
    r.snapped_vertex_of_split = Eigen::Map<const IndexVector>(snapped_.data(), static_cast<Index>(snapped_.size()));
    r.split_of_vertex = IndexVector::Constant(vertex_count, -1);
    for (Index i = 0; i < static_cast<Index>(created_by_.size()); ++i)
      r.split_of_vertex(input_vertices_ + i) = created_by_[i];

    const Index count = static_cast<Index>(tuples_.size());
    r.applied_simplex = SimplexMatrix::Constant(count, k_, -1);
    r.applied_barycentric = PointMatrix::Zero(count, k_);
    for (Index t = 0; t < count; ++t) {
      if (new_vertex_[t] < 0) continue;
      const Tuple& u = tuples_[t];  // left as applied: apply() no longer touches it
      for (int c = 0; c < u.n; ++c) {
        r.applied_simplex(t, c) = u.v[c];
        r.applied_barycentric(t, c) = u.b[c];
      }
    }

    // New vertices only refer to earlier ones, so one pass in creation order
    // interpolates attributes exactly as the points were.
    for (const auto& [name, table] : input.vertex_attributes) {
      PointMatrix out(vertex_count, table.cols());
      out.topRows(input_vertices_) = table;
      for (Index i = 0; i < static_cast<Index>(created_by_.size()); ++i) {
        const Tuple& u = tuples_[created_by_[i]];
        auto row = out.row(input_vertices_ + i);
        row.setZero();
        for (int c = 0; c < u.n; ++c) row += u.b[c] * out.row(u.v[c]);
      }
      r.complex.vertex_attributes[name] = std::move(out);
    }
    for (const auto& [name, table] : input.simplex_attributes)
      r.complex.simplex_attributes[name] = table(r.parent_simplex, Eigen::all);
    return r;
  }

 private:
  const Index* row(Index s) const { return &simplices_[static_cast<size_t>(s) * k_]; }
  const double* point(Index v) const { return &points_[static_cast<size_t>(v) * D_]; }

  bool row_contains(Index s, Index v) const {
    const Index* r = row(s);
    return std::find(r, r + k_, v) != r + k_;
  }

  // The top simplices containing all of `ids`: the incident simplices of its
  // vertex with the smallest star, filtered.
  void tops_containing(const Index* ids, int n, std::vector<Index>& out) const {
    out.clear();
    Index pivot = ids[0];
    for (int c = 1; c < n; ++c)
      if (star_[ids[c]].size() < star_[pivot].size()) pivot = ids[c];
    for (Index s : star_[pivot]) {
      bool all = true;
      for (int c = 0; c < n && all; ++c) all = row_contains(s, ids[c]);
      if (all) out.push_back(s);
    }
  }

  void insert_pending(Index t) {
    const Tuple& u = tuples_[t];
    pending_by_simplex_.emplace(make_key(u.v.data(), u.n), t);
  }

  void erase_pending(Index t) {
    const Tuple& u = tuples_[t];
    auto [first, last] = pending_by_simplex_.equal_range(make_key(u.v.data(), u.n));
    for (auto it = first; it != last; ++it)
      if (it->second == t) {
        pending_by_simplex_.erase(it);
        return;
      }
  }

  // §6.3: drops coordinates below epsilon (and exact zeros, which a tie in
  // the ratio test leaves) and renormalises. Returns false, and records the
  // vertex it snapped to, when fewer than two coordinates remain.
  bool sliver_control(Index t) {
    Tuple& u = tuples_[t];
    int largest = 0;
    for (int c = 1; c < u.n; ++c)
      if (u.b[c] > u.b[largest]) largest = c;
    const Index nearest = u.v[largest];
    int kept = 0;
    double sum = 0;
    for (int c = 0; c < u.n; ++c)
      if (u.b[c] > 0 && u.b[c] >= epsilon_) {
        u.v[kept] = u.v[c];
        u.b[kept] = u.b[c];
        sum += u.b[c];
        ++kept;
      }
    if (kept < 2) {
      u.pending = false;
      snapped_[t] = nearest;
      return false;
    }
    u.n = kept;
    for (int c = 0; c < kept; ++c) u.b[c] /= sum;
    return true;
  }

  // Eq. 6.1 and the ratio test: tuple t lies on a simplex g containing the
  // just-split face f (coordinates gamma, new vertex q). Moves it to the
  // child simplex that holds its point.
  void rehome(Index t, const Index* f, const double* gamma, int m, Index q) {
    Tuple& u = tuples_[t];
    std::array<double, kMax> g{};  // gamma over g's vertices; 0 off f (§6.1)
    for (int i = 0; i < u.n; ++i)
      for (int c = 0; c < m; ++c)
        if (f[c] == u.v[i]) g[i] = gamma[c];
    int j = -1;
    double ratio = std::numeric_limits<double>::infinity();
    for (int i = 0; i < u.n; ++i)
      if (g[i] > 0 && u.b[i] / g[i] < ratio) {
        ratio = u.b[i] / g[i];
        j = i;
      }
    // j exists: f is a face of g and every coordinate of f is positive.
    for (int i = 0; i < u.n; ++i)
      if (i != j) u.b[i] = std::max(u.b[i] - g[i] * ratio, 0.0);
    // q is the newest, hence largest, vertex id: moving it to the end keeps
    // the ids sorted.
    for (int i = j; i + 1 < u.n; ++i) {
      u.v[i] = u.v[i + 1];
      u.b[i] = u.b[i + 1];
    }
    u.v[u.n - 1] = q;
    u.b[u.n - 1] = ratio;
  }

  // Calls visit(tuple) once for every pending tuple whose simplex is a face of
  // top simplex s containing all vertices of `required` (a bit mask over s's
  // sorted vertices) and at least `min_size` vertices.
  template <class Visit>
  void for_each_pending_face(Index s, const Index* f, int m, int min_size, Visit&& visit) {
    std::array<Index, kMax> sorted;
    std::copy(row(s), row(s) + k_, sorted.begin());
    std::sort(sorted.begin(), sorted.begin() + k_);
    unsigned required = 0;
    for (int c = 0; c < k_; ++c)
      if (std::find(f, f + m, sorted[c]) != f + m) required |= 1u << c;
    const unsigned all = (1u << k_) - 1;
    Key key;
    // Enumerate the supersets of `required` within s.
    for (unsigned mask = required;; mask = (mask + 1) | required) {
      if (std::popcount(mask) >= min_size) {
        key.v.fill(-1);
        int n = 0;
        for (int c = 0; c < k_; ++c)
          if (mask & (1u << c)) key.v[n++] = sorted[c];
        auto [first, last] = pending_by_simplex_.equal_range(key);
        for (auto it = first; it != last; ++it) visit(it->second);
      }
      if (mask == all) break;
    }
  }

  // The cost of §6.3: the worst degeneracy among the simplices the split
  // would create right now.
  double cost(Index t) {
    const Tuple& u = tuples_[t];
    std::array<double, 16> q_small;
    std::vector<double> q_large;
    double* q = q_small.data();
    if (D_ > 16) {
      q_large.resize(D_);
      q = q_large.data();
    }
    std::fill(q, q + D_, 0.0);
    for (int c = 0; c < u.n; ++c) {
      const double* p = point(u.v[c]);
      for (int d = 0; d < D_; ++d) q[d] += u.b[c] * p[d];
    }
    tops_containing(u.v.data(), u.n, scratch_tops_);
    double worst = 0;
    std::array<const double*, kMax> corners;
    for (Index s : scratch_tops_) {
      const Index* r = row(s);
      for (int c = 0; c < k_; ++c) corners[c] = point(r[c]);
      for (int i = 0; i < u.n; ++i) {
        const int position = static_cast<int>(std::find(r, r + k_, u.v[i]) - r);
        const double* replaced = corners[position];
        corners[position] = q;
        worst = std::max(worst, degeneracy_of(corners.data(), k_, D_));
        corners[position] = replaced;
      }
    }
    return worst;
  }

  void push_cost(Index t) {
    Tuple& u = tuples_[t];
    ++u.version;
    queue_.push({cost(t), t, u.version});
  }

  // Splits top simplex s around face f with the new vertex q: the first
  // vertex of f (in s's order) is replaced in place, the children for the
  // other vertices of f are appended. Keeps the stars up to date.
  void split_top(Index s, const Index* f, int m, Index q) {
    std::array<Index, kMax> original;
    std::copy(row(s), row(s) + k_, original.begin());
    std::array<int, kMax> positions;
    int found = 0;
    for (int c = 0; c < k_; ++c)
      if (std::find(f, f + m, original[c]) != f + m) positions[found++] = c;
    for (int i = 1; i < m; ++i) {
      const Index child = static_cast<Index>(simplices_.size() / k_);
      for (int c = 0; c < k_; ++c) {
        const Index v = c == positions[i] ? q : original[c];
        simplices_.push_back(v);
        star_[v].push_back(child);
      }
      parent_.push_back(parent_[s]);
      changed_tops_.push_back(child);
    }
    simplices_[static_cast<size_t>(s) * k_ + positions[0]] = q;
    star_[q].push_back(s);
    auto& old_star = star_[original[positions[0]]];
    const auto it = std::find(old_star.begin(), old_star.end(), s);
    *it = old_star.back();
    old_star.pop_back();
    changed_tops_.push_back(s);
  }

  void apply(Index t) {
    erase_pending(t);
    Tuple& u = tuples_[t];
    u.pending = false;
    const int m = u.n;
    std::array<Index, kMax> f;
    std::array<double, kMax> gamma;
    std::copy(u.v.begin(), u.v.begin() + m, f.begin());
    std::copy(u.b.begin(), u.b.begin() + m, gamma.begin());

    const Index q = static_cast<Index>(points_.size() / D_);
    for (int d = 0; d < D_; ++d) {
      double x = 0;
      for (int c = 0; c < m; ++c) x += gamma[c] * point(f[c])[d];
      points_.push_back(x);
    }
    star_.emplace_back();
    new_vertex_[t] = q;
    created_by_.push_back(t);

    // The tuples this split invalidates: those on a simplex containing f.
    tops_containing(f.data(), m, split_tops_);
    ++stamp_;
    affected_.clear();
    for (Index s : split_tops_)
      for_each_pending_face(s, f.data(), m, m, [&](Index other) {
        if (mark_[other] != stamp_) {
          mark_[other] = stamp_;
          affected_.push_back(other);
        }
      });
    for (Index other : affected_) erase_pending(other);

    changed_tops_.clear();
    for (Index s : split_tops_) split_top(s, f.data(), m, q);

    for (Index other : affected_) {
      rehome(other, f.data(), gamma.data(), m, q);
      if (sliver_control(other)) insert_pending(other);
    }

    if (order_ == RefineOrder::Degeneracy) {
      // Every tuple whose star changed: those on a face (of two or more
      // vertices) of a changed simplex; the re-homed ones are among them.
      ++stamp_;
      for (Index s : changed_tops_)
        for_each_pending_face(s, nullptr, 0, 2, [&](Index other) {
          if (mark_[other] != stamp_) {
            mark_[other] = stamp_;
            push_cost(other);
          }
        });
    }
  }

  const int k_;
  const int D_;
  const Index input_vertices_;
  const double epsilon_;
  const RefineOrder order_;

  std::vector<double> points_;       // #V' by D, row-major
  std::vector<Index> simplices_;     // #S' by k, row-major
  std::vector<Index> parent_;        // #S'
  std::vector<std::vector<Index>> star_;  // vertex -> incident top simplices

  std::vector<Tuple> tuples_;
  std::unordered_multimap<Key, Index, KeyHash> pending_by_simplex_;
  std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<>> queue_;
  std::vector<std::uint32_t> mark_;  // per tuple: stamp_ when last visited
  std::uint32_t stamp_ = 0;

  std::vector<Index> new_vertex_;  // per tuple
  std::vector<Index> snapped_;     // per tuple
  std::vector<Index> created_by_;  // per new vertex, in creation order

  std::vector<Index> split_tops_, changed_tops_, affected_, scratch_tops_;
};

}  // namespace

Eigen::VectorXd edge_length_degeneracy(const PointMatrix& V, const SimplexMatrix& S) {
  const int k = static_cast<int>(S.cols());
  if (k > kMax) fail<InputError>("simplices with ", k, " vertices are not supported (at most ", kMax, ")");
  Eigen::VectorXd out(S.rows());
  std::array<const double*, kMax> corners;
  for (Index s = 0; s < S.rows(); ++s) {
    for (int c = 0; c < k; ++c) {
      const Index v = S(s, c);
      if (v < 0 || v >= V.rows())
        fail<InputError>("simplex ", s, " refers to vertex ", v, ", outside 0..", V.rows() - 1);
      corners[c] = V.row(v).data();
    }
    out(s) = degeneracy_of(corners.data(), k, static_cast<int>(V.cols()));
  }
  return out;
}

Refinement refine(const Complex& input, const SimplexMatrix& split_vertices, const PointMatrix& split_barycentric,
                  const RefineOptions& options) {
  check_memory(refinement_memory(input, split_vertices));
  input.validate();
  const int k = static_cast<int>(input.S.cols());
  if (k < 2 || k > kMax)
    fail<InputError>("refine supports simplices of 2..", kMax, " vertices, got ", k);
  // A simplex repeating a vertex has no well-defined children (which copy
  // would the new vertex replace?).
  for (Index s = 0; s < input.S.rows(); ++s)
    for (int a = 0; a < k; ++a)
      for (int b = a + 1; b < k; ++b)
        if (input.S(s, a) == input.S(s, b))
          fail<InputError>("simplex ", s, " repeats vertex ", input.S(s, a));
  if (!(options.epsilon >= 0 && options.epsilon < 0.5))
    fail<InputError>("epsilon ", options.epsilon, " is outside [0, 0.5)");
  if (split_vertices.rows() != split_barycentric.rows() || split_vertices.cols() != split_barycentric.cols())
    fail<InputError>("split vertices are ", split_vertices.rows(), " by ", split_vertices.cols(),
                     " but their barycentric coordinates are ", split_barycentric.rows(), " by ",
                     split_barycentric.cols());
  const Index count = static_cast<Index>(split_vertices.rows());
  if (count > 0 && split_vertices.cols() > k)
    fail<InputError>("splits name up to ", split_vertices.cols(), " vertices but the simplices have ", k);

  Refiner refiner(input, options, count);
  for (Index t = 0; t < count; ++t)
    refiner.add_tuple(t, split_vertices.row(t).data(), split_barycentric.row(t).data(),
                      static_cast<int>(split_vertices.cols()));
  refiner.run();
  return refiner.result(input);
}

}  // namespace animanifold
