#include "slice_weld.hpp"

#include "animanifold/threads.hpp"
#include "slice_points.hpp"

#include <atomic>
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

// Per chunk, its keys' positions grouped by the thread that owns them (each
// group in chunk order), and where each thread's group starts: a thread then
// walks only its own keys, with no branch on the owner per key.
struct Owned {
  std::vector<std::uint32_t> positions;
  std::vector<std::uint32_t> start;  // teams + 1 entries
};

void group_by_owner(std::span<const std::uint64_t> chunk, int teams, Owned& out) {
  out.start.assign(teams + 1, 0);
  out.positions.resize(chunk.size());
  std::vector<int> owners(chunk.size());
  for (size_t i = 0; i < chunk.size(); ++i) {
    owners[i] = owner(static_cast<Index>(chunk[i] >> 32), teams);
    ++out.start[owners[i] + 1];
  }
  for (int t = 0; t < teams; ++t) out.start[t + 1] += out.start[t];
  std::vector<std::uint32_t> next(out.start.begin(), out.start.end() - 1);
  for (size_t i = 0; i < chunk.size(); ++i) out.positions[next[owners[i]]++] = static_cast<std::uint32_t>(i);
}

// One thread's share: the keys it owns. Writes the position of each such
// key's first key (its own for a first key) into `first_of`, and lists its
// points in `links`. `head` (an entry per vertex a) is -1 before and after.
void weld_share(const std::vector<std::span<const std::uint64_t>>& keys, const std::vector<size_t>& offset,
                const std::vector<Owned>& owned, int team, Index* head, std::vector<Link>& links, Index* first_of) {
  links.clear();
  try {
    for (size_t c = 0; c < keys.size(); ++c) {
      const std::span<const std::uint64_t> chunk = keys[c];
      const Owned& mine = owned[c];
      for (std::uint32_t o = mine.start[team]; o < mine.start[team + 1]; ++o) {
        const std::uint32_t i = mine.positions[o];
        const Index a = static_cast<Index>(chunk[i] >> 32), b = static_cast<Index>(chunk[i] & 0xffffffffu);
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
  std::vector<Owned> owned(chunks);
  std::exception_ptr failure;  // read once the threads are done
  std::atomic<bool> failed{false};
  auto record = [&] {
    failed = true;
#pragma omp critical(slice_weld_failure)
    if (!failure) failure = std::current_exception();
  };
#pragma omp parallel num_threads(thread_count()) if (total > kParallelKeys)
  {
    const int teams = omp_get_num_threads(), team = omp_get_thread_num();
#pragma omp for schedule(static)
    for (std::ptrdiff_t c = 0; c < chunks; ++c) {
      try {
        group_by_owner(keys[c], teams, owned[c]);
      } catch (...) {
        record();
      }
    }
    // Past the loop's closing barrier every thread sees a failure in it.
    // Per thread and kept between slices, at -1 but while a weld runs.
    thread_local std::vector<Index> head;
    thread_local std::vector<Link> links;
    if (!failed) {
      try {
        if (head.size() < static_cast<size_t>(m.V.rows())) head.resize(m.V.rows(), -1);
        weld_share(keys, offset, owned, team, head.data(), links, first_of.get());
      } catch (...) {
        record();
      }
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
