#include "zero_set.hpp"

#include "animanifold/errors.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>

namespace animanifold {

namespace {

constexpr int kMaxCorners = 5;

// One piece of the zero set of a simplex whose vertices are in ascending id
// order: its corners as (negative vertex, positive vertex) positions, in an
// order that makes it positive when that sorted simplex is.
struct Piece {
  std::array<std::array<signed char, 2>, kMaxCorners - 1> corner;
};

// pieces[k][mask]: the staircase pieces for a simplex of k vertices whose
// negative vertices (in sorted position) are the bits of `mask`.
struct PieceTables {
  std::array<std::array<std::vector<Piece>, 1 << kMaxCorners>, kMaxCorners + 1> pieces;

  PieceTables() {
    for (int k = 4; k <= kMaxCorners; ++k)
      for (int mask = 1; mask + 1 < (1 << k); ++mask) pieces[k][mask] = staircase(k, mask);
  }

  static std::vector<Piece> staircase(int k, int mask) {
    std::vector<int> negative, positive;
    for (int v = 0; v < k; ++v) ((mask >> v) & 1 ? negative : positive).push_back(v);
    const int n_steps = static_cast<int>(negative.size()) - 1, steps = k - 2;
    std::vector<Piece> out;
    // Each path takes `steps` steps, n_steps of them along N: bit j of `path` set = step j advances N.
    for (int path = 0; path < (1 << steps); ++path) {
      if (__builtin_popcount(static_cast<unsigned>(path)) != n_steps) continue;
      Piece piece{};
      int i = 0, j = 0;
      for (int c = 0; c < k - 1; ++c) {
        piece.corner[c] = {static_cast<signed char>(negative[i]), static_cast<signed char>(positive[j])};
        if (c < steps) ((path >> c) & 1 ? i : j)++;
      }
      // Barycentric rows: each corner at the middle of its edge, then a vertex of P.
      Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(k, k);
      for (int c = 0; c < k - 1; ++c) rows(c, piece.corner[c][0]) = rows(c, piece.corner[c][1]) = 0.5;
      rows(k - 1, positive.front()) = 1.0;
      if (rows.determinant() < 0) std::swap(piece.corner[0], piece.corner[1]);
      out.push_back(piece);
    }
    return out;
  }
};

const PieceTables& tables() {
  static const PieceTables t;
  return t;
}

constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

std::uint64_t edge_key(Index a, Index b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

size_t slot_of(std::uint64_t key, size_t mask) { return (key * 0x9E3779B97F4A7C15ull) >> 17 & mask; }

}  // namespace

ZeroSetBuilder::ZeroSetBuilder(int corners, size_t expected_cuts) : corners_(corners) {
  if (corners != 4 && corners != 5) fail<InputError>("marching simplices takes 4 or 5 corners, got ", corners);
  size_t capacity = 16;
  while (capacity < 2 * expected_cuts + 16) capacity <<= 1;
  keys_.assign(capacity, kEmpty);
  slots_.resize(capacity);
  mask_ = capacity - 1;
  cuts_.reserve(expected_cuts);
  tables();
}

void ZeroSetBuilder::grow() {
  keys_.assign(keys_.size() * 2, kEmpty);
  slots_.resize(keys_.size());
  mask_ = keys_.size() - 1;
  for (size_t c = 0; c < cuts_.size(); ++c) {
    const std::uint64_t key = edge_key(cuts_[c].a, cuts_[c].b);
    size_t slot = slot_of(key, mask_);
    while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
    keys_[slot] = key;
    slots_[slot] = static_cast<Index>(c);
  }
}

// The cut on the edge from a (value < 0) to b (value >= 0).
Index ZeroSetBuilder::cut(Index a, Index b, double va, double vb) {
  ZeroCut point;
  if (vb == 0.0) {
    point = {b, b, 0.0};
  } else {
    const double from_a = va / (va - vb);  // in (0, 1): va < 0 < vb
    point = a < b ? ZeroCut{a, b, from_a} : ZeroCut{b, a, 1.0 - from_a};
  }
  return intern(point);
}

Index ZeroSetBuilder::intern(const ZeroCut& point) {
  const std::uint64_t key = edge_key(point.a, point.b);
  size_t slot = slot_of(key, mask_);
  while (keys_[slot] != kEmpty) {
    if (keys_[slot] == key) return slots_[slot];
    slot = (slot + 1) & mask_;
  }
  if (2 * (cuts_.size() + 1) > keys_.size()) {
    grow();
    slot = slot_of(key, mask_);
    while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
  }
  keys_[slot] = key;
  slots_[slot] = static_cast<Index>(cuts_.size());
  cuts_.push_back(point);
  return slots_[slot];
}

void ZeroSetBuilder::append(const ZeroSetBuilder& other) {
  if (other.corners_ != corners_)
    fail<InputError>("cannot append a zero set of ", other.corners_, "-corner simplices to one of ", corners_);
  std::vector<Index> index(other.cuts_.size());
  for (size_t c = 0; c < other.cuts_.size(); ++c) index[c] = intern(other.cuts_[c]);
  pieces_.reserve(pieces_.size() + other.pieces_.size());
  for (const Index c : other.pieces_) pieces_.push_back(index[static_cast<size_t>(c)]);
  sources_.insert(sources_.end(), other.sources_.begin(), other.sources_.end());
}

void ZeroSetBuilder::add(const Index* ids, const double* value, Index source) {
  const int k = corners_;
  // Ascending ids, and the parity of the permutation that sorts them.
  std::array<int, kMaxCorners> order;
  for (int c = 0; c < k; ++c) order[c] = c;
  bool odd = false;
  for (int i = 1; i < k; ++i)
    for (int j = i; j > 0 && ids[order[j - 1]] > ids[order[j]]; --j) std::swap(order[j - 1], order[j]), odd = !odd;
  int mask = 0;
  for (int c = 0; c < k; ++c) mask |= (value[order[c]] < 0.0) << c;
  if (mask == 0 || mask == (1 << k) - 1) return;
  for (const Piece& piece : tables().pieces[k][mask]) {
    std::array<Index, kMaxCorners - 1> corner;
    for (int c = 0; c < k - 1; ++c) {
      const int n = order[piece.corner[c][0]], p = order[piece.corner[c][1]];
      corner[c] = cut(ids[n], ids[p], value[n], value[p]);
    }
    bool collapsed = false;
    for (int a = 0; a < k - 1 && !collapsed; ++a)
      for (int b = a + 1; b < k - 1; ++b) collapsed = collapsed || corner[a] == corner[b];
    if (collapsed) continue;
    if (odd) std::swap(corner[0], corner[1]);
    pieces_.insert(pieces_.end(), corner.begin(), corner.begin() + (k - 1));
    sources_.push_back(source);
  }
}

}  // namespace animanifold
