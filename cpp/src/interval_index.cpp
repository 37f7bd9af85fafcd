// The interval index (slice.hpp): an implicit interval tree over the
// simplices' extents along one axis, 12 bytes a simplex.
#include "animanifold/errors.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/threads.hpp"
#include "huge_pages.hpp"
#include "slice_points.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <utility>
#include <cmath>
#include <exception>
#include <limits>

namespace animanifold {

namespace {

// The simplex's exact extent [low, high] along the axis.
std::pair<double, double> extent(const PointMatrix& V, const SimplexMatrix& S, Index s, int axis) {
  double low = V(S(s, 0), axis), high = low;
  for (int c = 1; c < S.cols(); ++c) {
    const double x = V(S(s, c), axis);
    low = std::min(low, x);
    high = std::max(high, x);
  }
  return {low, high};
}

// Room for `count` items in a fresh vector, on huge pages where the kernel
// grants them: the index of a large manifold is walked at random.
template <typename T>
void reserve_huge(std::vector<T>& items, Index count) {
  items.reserve(count);
  advise_huge_pages(items.data(), sizeof(T) * items.capacity());
}

// The nearest float at or below (above) x: the tree's bounds hold the exact ones.
float float_below(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float float_above(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Sorts (low, simplex) pairs, given in simplex order, by low and then
// simplex: a stable least-significant-digit radix sort on the doubles' bits
// (as unsigned integers they order like the doubles once the sign bit is
// flipped, and every bit of a negative one), 11 bits a pass, skipping the
// passes whose digit all keys share. It runs on one thread in linear time:
// the index of a 4M-tet zero set is built beside the morph's other checks,
// where a comparison sort took half the index's time.
void sort_by_low(std::vector<std::pair<double, Index>>& items) {
  constexpr int kBits = 11, kPasses = (64 + kBits - 1) / kBits;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kBits) - 1;
  struct Record {
    std::uint64_t key;
    Index simplex;
  };
  const size_t n = items.size();
  std::vector<Record> records(n), spare(n);
  std::vector<std::array<size_t, kMask + 1>> count(kPasses);
  for (auto& c : count) c.fill(0);
  for (size_t i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, &items[i].first, sizeof bits);
    if (bits == std::uint64_t{1} << 63) bits = 0;  // -0 ties with +0, as it compares
    const std::uint64_t key = bits >> 63 ? ~bits : bits | (std::uint64_t{1} << 63);
    records[i] = {key, items[i].second};
    for (int pass = 0; pass < kPasses; ++pass) ++count[pass][(key >> (kBits * pass)) & kMask];
  }
  for (int pass = 0; pass < kPasses; ++pass) {
    std::array<size_t, kMask + 1>& c = count[pass];
    if (std::find(c.begin(), c.end(), n) != c.end()) continue;  // one digit for all: nothing moves
    size_t at = 0;
    for (size_t& bucket : c) at += std::exchange(bucket, at);
    for (const Record& r : records) spare[c[(r.key >> (kBits * pass)) & kMask]++] = r;
    records.swap(spare);
  }
  for (size_t i = 0; i < n; ++i) {
    const std::uint64_t key = records[i].key;
    const std::uint64_t bits = key >> 63 ? key & ~(std::uint64_t{1} << 63) : ~key;
    std::memcpy(&items[i].first, &bits, sizeof bits);
    items[i].second = records[i].simplex;
  }
}

}  // namespace

IntervalIndex::IntervalIndex(const PointMatrix& V, const SimplexMatrix& S, int axis)
    : vertex_count_(V.rows()), axis_(axis) {
  if (axis < 0 || axis >= V.cols()) fail<InputError>("axis ", axis, " is outside 0..", V.cols() - 1);
  // Sorted by exact low (then simplex), as the tree's order decides the
  // order stab() reports hits in, and with it the order of a slice's output.
  std::vector<std::pair<double, Index>> by_low;
  std::vector<float> high;
  reserve_huge(by_low, S.rows()), reserve_huge(high, S.rows()), reserve_huge(nodes_, S.rows());
  by_low.resize(S.rows()), high.resize(S.rows());
  lowest_ = std::numeric_limits<double>::infinity();
  highest_ = -lowest_;
  double lowest = lowest_, highest = highest_;
#pragma omp parallel for schedule(static) reduction(min : lowest) reduction(max : highest) num_threads(thread_count())
  for (Index s = 0; s < S.rows(); ++s) {
    const auto [low, hi] = extent(V, S, s, axis);
    by_low[s] = {low, s};
    high[s] = float_above(hi);
    lowest = std::min(lowest, low);
    highest = std::max(highest, hi);
  }
  lowest_ = lowest, highest_ = highest;
  // The keys are distinct (the simplex breaks ties), so the sorted order,
  // and the tree, are the same on any thread count.
  if (!std::is_sorted(by_low.begin(), by_low.end())) sort_by_low(by_low);
  nodes_.resize(S.rows());
  for (size_t i = 0; i < by_low.size(); ++i) nodes_[i] = {float_below(by_low[i].first), high[by_low[i].second],
                                                          by_low[i].second};
  std::vector<std::pair<double, Index>>().swap(by_low);
  // The tree is implicit: the root of a range [lo, hi) is its midpoint.
  // subtree_high of a root is the largest (rounded-up) high in its range.
  struct Builder {
    std::vector<Node>& nodes;
    float build(size_t lo, size_t hi) {
      if (lo >= hi) return -std::numeric_limits<float>::infinity();
      const size_t mid = lo + (hi - lo) / 2;
      const float h = std::max({nodes[mid].subtree_high, build(lo, mid), build(mid + 1, hi)});
      nodes[mid].subtree_high = h;
      return h;
    }
  };
  Builder{nodes_}.build(0, nodes_.size());
  vertex_values_.assign(V.col(axis).begin(), V.col(axis).end());
  std::sort(vertex_values_.begin(), vertex_values_.end());
  vertex_values_.erase(std::unique(vertex_values_.begin(), vertex_values_.end()), vertex_values_.end());
  vertex_values_.shrink_to_fit();
}

std::optional<std::pair<double, double>> IntervalIndex::topology_interval(double value) const {
  // The same snap as slice(): a value it would move onto a vertex has that vertex's faces.
  const double snap = slice_points::snap_tolerance(lowest_, highest_);
  const auto above = std::upper_bound(vertex_values_.begin(), vertex_values_.end(), value);
  if (above == vertex_values_.begin() || above == vertex_values_.end()) return std::nullopt;
  const double lo = *(above - 1), hi = *above;
  if (value - lo <= snap || hi - value <= snap) return std::nullopt;
  return std::make_pair(lo, hi);
}

bool IntervalIndex::has_vertex_value_near(double value, double tolerance) const {
  const auto above = std::lower_bound(vertex_values_.begin(), vertex_values_.end(), value);
  if (above != vertex_values_.end() && *above - value <= tolerance) return true;
  return above != vertex_values_.begin() && value - *(above - 1) <= tolerance;
}

namespace {

// Subtrees of at most this many nodes are stabbed as one piece of work.
constexpr size_t kPieceNodes = 16384;

}  // namespace

// A piece of a parallel stab, in the in-order sequence: a root above the
// pieces (one hit) or a subtree [lo, hi) to stab.
struct IntervalIndex::StabPiece {
  size_t lo, hi;
  Index hit;  // the root's simplex, when hi == lo
};

void IntervalIndex::stab_candidates(double value, std::vector<Index>& out) const {
  if (nodes_.size() <= kPieceNodes || thread_count() == 1) {
    stab_range(0, nodes_.size(), value, out);
    return;
  }
  // The roots above the pieces are visited here, in order; the pieces, each
  // into its own list, on OpenMP's threads. Joined in order, the hits are
  // those of the serial walk, in its order, for any thread count.
  std::vector<StabPiece> pieces;
  plan_stab(0, nodes_.size(), value, pieces);
  std::vector<std::vector<Index>> hits(pieces.size());
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(pieces.size());
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count()) if (count > 1)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    if (pieces[i].hi == pieces[i].lo) continue;
    try {
      stab_range(pieces[i].lo, pieces[i].hi, value, hits[i]);
    } catch (...) {
#pragma omp critical(interval_stab_failure)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  size_t total = out.size();
  for (std::ptrdiff_t i = 0; i < count; ++i) total += pieces[i].hi == pieces[i].lo ? 1 : hits[i].size();
  out.reserve(total);
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    if (pieces[i].hi == pieces[i].lo) out.push_back(pieces[i].hit);
    else out.insert(out.end(), hits[i].begin(), hits[i].end());
  }
}

void IntervalIndex::plan_stab(size_t lo, size_t hi, double value, std::vector<StabPiece>& pieces) const {
  // stab_range()'s walk, down to subtrees of kPieceNodes.
  while (lo < hi) {
    if (hi - lo <= kPieceNodes) {
      pieces.push_back({lo, hi, -1});
      return;
    }
    const size_t mid = lo + (hi - lo) / 2;
    const Node& node = nodes_[mid];
    if (node.subtree_high < value) return;
    plan_stab(lo, mid, value, pieces);
    if (node.low > value) return;
    pieces.push_back({mid, mid, node.simplex});
    lo = mid + 1;
  }
}

void IntervalIndex::stab_range(size_t lo, size_t hi, double value, std::vector<Index>& out) const {
  // In order: left subtree, root, right subtree, so hits come out in the
  // nodes' order (by low, then simplex), and a stitched manifold's hits
  // (one slab, one low) in the order of its table. The recursion goes as
  // deep as the tree (log2 #S); the right subtree is this loop's next turn.
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    const Node& node = nodes_[mid];
    if (node.subtree_high < value) return;  // nothing in this range reaches the value
    stab_range(lo, mid, value, out);
    if (node.low > value) return;  // the right subtree starts at or after node.low
    out.push_back(node.simplex);
    lo = mid + 1;
  }
}

void IntervalIndex::stab(const PointMatrix& V, const SimplexMatrix& S, double value, std::vector<Index>& out) const {
  if (V.rows() != vertex_count_ || S.rows() != static_cast<Index>(nodes_.size()) || V.cols() <= axis_)
    fail<InputError>("the interval index was built on ", vertex_count_, " points and ", nodes_.size(),
                     " simplices, not on these ", V.rows(), " points and ", S.rows(), " simplices");
  const size_t first = out.size();
  stab_candidates(value, out);
  // The float bounds hold the exact extent; the points decide.
  const auto exact_end = std::remove_if(out.begin() + first, out.end(), [&](Index s) {
    const auto [low, high] = extent(V, S, s, axis_);
    return !(low <= value && value <= high);
  });
  out.erase(exact_end, out.end());
}

size_t IntervalIndex::memory_bytes() const {
  return nodes_.capacity() * sizeof(Node) + vertex_values_.capacity() * sizeof(double);
}

}  // namespace animanifold
