#include "slice_weld.hpp"

#include "animanifold/threads.hpp"
#include "slice_points.hpp"

#include <exception>
#include <memory>
#include <omp.h>

namespace animanifold::slice_cut {

namespace {

// Keys from which the weld runs on OpenMP's threads.
constexpr size_t kParallelKeys = 65536;

struct Link {
  Index a, b;
  Index next;   // the previous point of this thread with the same a (-1: none)
  Index first;  // the position of its first key among all keys
};

// The thread that owns the keys of lower vertex a: a multiplicative hash of
// a, spread over the threads (a division per key would cost more than the
// weld's list walk).
int owner(Index a, int teams) {
  return static_cast<int>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(a) * 0x9E3779B9u) * teams) >> 32);
}

// One thread's share: the keys it owns. Writes the position of each such
// key's first key (its own for a first key) into `first_of`, and lists its
// points in `links`. `head` (an entry per vertex a) is -1 before and after.
void weld_share(const std::vector<std::span<const std::uint64_t>>& keys, const std::vector<size_t>& offset, int team,
                int teams, std::vector<Index>& head, std::vector<Link>& links, Index* first_of) {
  links.clear();
  try {
    for (size_t c = 0; c < keys.size(); ++c) {
      const std::span<const std::uint64_t> chunk = keys[c];
      for (size_t i = 0; i < chunk.size(); ++i) {
        const Index a = static_cast<Index>(chunk[i] >> 32), b = static_cast<Index>(chunk[i] & 0xffffffffu);
        if (owner(a, teams) != team) continue;
        const Index g = static_cast<Index>(offset[c] + i);
        Index& list = head[a];
        Index id = list;
        while (id >= 0 && links[id].b != b) id = links[id].next;
        if (id < 0) {
          id = static_cast<Index>(links.size());
          links.push_back({a, b, list, g});
          list = id;
        }
        first_of[g] = links[id].first;
      }
    }
  } catch (...) {
    for (const Link& link : links) head[link.a] = -1;
    throw;
  }
  for (const Link& link : links) head[link.a] = -1;
}

}  // namespace

void weld(const Complex& m, int axis, double value, const std::vector<std::span<const std::uint64_t>>& keys,
          const std::vector<std::span<Index>>& ids, std::vector<Point>& points) {
  const std::ptrdiff_t chunks = static_cast<std::ptrdiff_t>(keys.size());
  std::vector<size_t> offset(chunks + 1, 0);
  for (std::ptrdiff_t c = 0; c < chunks; ++c) offset[c + 1] = offset[c] + keys[c].size();
  const size_t total = offset.back();
  // Per key: the position of its point's first key, then (below) for a first key -1 - its point.
  // Every entry is written by the thread owning its key, so none is initialised.
  const std::unique_ptr<Index[]> first_of(new Index[total]);
  std::exception_ptr failure;
#pragma omp parallel num_threads(thread_count()) if (total > kParallelKeys)
  {
    // Per thread and kept between slices, at -1 but while a weld runs.
    thread_local std::vector<Index> head;
    thread_local std::vector<Link> links;
    try {
      if (head.size() < static_cast<size_t>(m.V.rows())) head.resize(m.V.rows(), -1);
      weld_share(keys, offset, omp_get_thread_num(), omp_get_num_threads(), head, links, first_of.get());
    } catch (...) {
#pragma omp critical(slice_weld_failure)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);

  // The points, numbered by their first key: chunk by chunk.
  std::vector<Index> first_point(chunks + 1, 0);
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (total > kParallelKeys)
  for (std::ptrdiff_t c = 0; c < chunks; ++c)
    for (size_t g = offset[c]; g < offset[c + 1]; ++g) first_point[c + 1] += first_of[g] == static_cast<Index>(g);
  for (std::ptrdiff_t c = 0; c < chunks; ++c) first_point[c + 1] += first_point[c];
  points.resize(first_point.back());
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (total > kParallelKeys)
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    Index p = first_point[c];
    for (size_t g = offset[c]; g < offset[c + 1]; ++g) {
      if (first_of[g] != static_cast<Index>(g)) continue;
      const std::uint64_t key = keys[c][g - offset[c]];
      const Index a = static_cast<Index>(key >> 32), b = static_cast<Index>(key & 0xffffffffu);
      points[p] = {a, b, a == b ? 0.0 : slice_points::edge_parameter(m.V, axis, value, a, b)};
      first_of[g] = -1 - p++;
    }
  }
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (total > kParallelKeys)
  for (std::ptrdiff_t c = 0; c < chunks; ++c)
    for (size_t g = offset[c]; g < offset[c + 1]; ++g) {
      const Index first = first_of[g];
      ids[c][g - offset[c]] = first < 0 ? -1 - first : -1 - first_of[first];
    }
}

}  // namespace animanifold::slice_cut
