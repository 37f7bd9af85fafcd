// A simplex, or a face of one, as a key for hash maps and sets: its vertex ids
// sorted (every ordering of the same corners gives the same key) and padded
// with -1 up to N. Used wherever cells are matched by their corners: a facet
// shared by two cells, faces already covered, cells already seen.
#pragma once

#include "animanifold/types.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace animanifold {

template <std::size_t N>
using SimplexKey = std::array<Index, N>;

// The key of the `count` (<= N) ids at `ids`.
template <std::size_t N>
SimplexKey<N> simplex_key(const Index* ids, int count) {
  SimplexKey<N> key;
  key.fill(-1);
  std::copy(ids, ids + count, key.begin());
  std::sort(key.begin(), key.begin() + count);
  return key;
}

// FNV-1a over the ids (their low 32 bits: ids are below 2^31).
struct SimplexKeyHash {
  template <std::size_t N>
  std::size_t operator()(const SimplexKey<N>& key) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (const Index v : key) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace animanifold
