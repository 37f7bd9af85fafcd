#include "slice_cut.hpp"

#include "animanifold/threads.hpp"
#include "slice_points.hpp"
#include "slice_stages.hpp"

#include <algorithm>
#include <array>
#include <cstdint>

namespace animanifold::slice_cut {

namespace {

// Candidates a chunk cuts: fixed, so chunks (and the output) do not depend on the threads.
constexpr size_t kChunk = 4096;

std::uint64_t pack(Index a, Index b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// One chunk's cut: the points in the order it meets them, as keys (a, b),
// a <= b (a key may come more than once), and each kept face's corners as
// positions among them.
struct Chunk {
  std::vector<std::uint64_t> keys;
  std::vector<Index> corners;
  std::vector<Index> simplex;
  std::vector<Index> ids;  // per key: its point (weld())
};

// Cuts simplices into a Chunk: the table of Figure 2.6.
class ChunkCutter {
 public:
  ChunkCutter(const Complex& m, int axis, double value, Chunk& out) : m_(m), axis_(axis), value_(value), out_(out) {}

  // Tets in R^4 -> triangles in R^3.
  void cut_tet(const Index* t, const bool* above, int above_count, Index source) {
    Index f[3];
    if (above_count == 1 || above_count == 3) {
      // The lone vertex and the opposite facet in its outward orientation.
      int apex = 0;
      while (above[apex] != (above_count == 1)) ++apex;
      facet(t, 4, apex, f);
      Index tri[3] = {point(t[apex], f[0]), point(t[apex], f[1]), point(t[apex], f[2])};
      if (above_count == 3) std::swap(tri[0], tri[1]);  // the part above lies away from the apex
      face(tri, 3, source);
      return;
    }
    // Two above (i, j), two below (k, l), with [i, j, k, l] an even permutation
    // of the tet: the quad (ik, il, jl, jk), split along its shorter diagonal.
    Index up[2], down[2];
    int position[4];
    for (int c = 0, u = 0, d = 0; c < 4; ++c) {
      if (above[c]) position[u] = c, up[u++] = t[c];
      else position[2 + d] = c, down[d++] = t[c];
    }
    if (permutation_parity(position, 4) < 0) std::swap(down[0], down[1]);
    const Index ik = point(up[0], down[0]), il = point(up[0], down[1]);
    const Index jl = point(up[1], down[1]), jk = point(up[1], down[0]);
    Index a[3] = {ik, il, jl}, b[3] = {ik, jl, jk};
    face(a, 3, source);
    face(b, 3, source);
  }

  // Triangles in R^3 -> segments in R^2.
  void cut_triangle(const Index* t, const bool* above, int above_count, Index source) {
    int apex = 0;
    while (above[apex] != (above_count == 1)) ++apex;
    Index f[2];
    facet(t, 3, apex, f);
    Index seg[2] = {point(t[apex], f[0]), point(t[apex], f[1])};
    if (above_count == 2) std::swap(seg[0], seg[1]);
    face(seg, 2, source);
  }

 private:
  // The point where the plane crosses edge (a, b), keyed (min, max), or
  // (v, v) where it passes through vertex v: both simplices sharing an edge
  // give the same key. Returns its position in the chunk's keys: an earlier
  // one when the key is among those the chunk met recently (the simplices
  // around an edge are mostly near one another in the candidates), so the
  // weld has fewer keys to number. Which keys repeat changes no point's first key.
  Index point(Index a, Index b) {
    if (a > b) std::swap(a, b);
    if (a != b) {
      const double s = slice_points::edge_parameter(m_.V, axis_, value_, a, b);
      if (s <= 0.0) b = a;          // the plane passes through a
      else if (s >= 1.0) a = b;     // ... or through b
    }
    const std::uint64_t key = pack(a, b);
    Index& recent = recent_[(key * 0x9E3779B97F4A7C15ull) >> (64 - kRecentBits)];
    // A slot may hold a position from an earlier chunk or another key: only a position with this key counts.
    if (static_cast<size_t>(recent) < out_.keys.size() && out_.keys[recent] == key) return recent;
    recent = static_cast<Index>(out_.keys.size());
    out_.keys.push_back(key);
    return recent;
  }

  void face(const Index* p, int n, Index source) {
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (out_.keys[p[i]] == out_.keys[p[j]]) return;  // collapsed: zero area
    out_.corners.insert(out_.corners.end(), p, p + n);
    out_.simplex.push_back(source);
  }

  static constexpr int kRecentBits = 10;

  const Complex& m_;
  int axis_;
  double value_;
  Chunk& out_;
  std::array<Index, 1 << kRecentBits> recent_{};  // by a hash of a key: the position it was last added at
};

// The candidates [begin, end) cut into `out`. On-plane vertices count as
// below, except when `on_plane_is_above` (the very top of the manifold).
void cut_chunk(const Complex& m, int axis, double value, bool on_plane_is_above, const Index* begin,
               const Index* end, Chunk& out) {
  const int k = m.vertices_per_simplex();
  out.keys.reserve(4 * (end - begin));
  out.corners.reserve(2 * (k - 1) * (end - begin));
  out.simplex.reserve(2 * (end - begin));
  ChunkCutter cutter(m, axis, value, out);
  bool above[4];
  // Candidates are scattered over the table: a simplex's row is fetched this
  // many candidates early, and its points' coordinates (which need the row) half as early.
  constexpr std::ptrdiff_t kRowsAhead = 24, kPointsAhead = 12;
  for (const Index* s = begin; s != end; ++s) {
    if (end - s > kRowsAhead) __builtin_prefetch(m.S.row(s[kRowsAhead]).data());
    if (end - s > kPointsAhead) {
      const Index* later = m.S.row(s[kPointsAhead]).data();
      for (int c = 0; c < k; ++c) __builtin_prefetch(&m.V(later[c], axis));
    }
    const Index* t = m.S.row(*s).data();
    int above_count = 0;
    for (int c = 0; c < k; ++c) {
      const double x = m.V(t[c], axis);
      above[c] = on_plane_is_above ? x >= value : x > value;
      above_count += above[c];
    }
    if (above_count == 0 || above_count == k) continue;
    if (k == 4) cutter.cut_tet(t, above, above_count, *s);
    else cutter.cut_triangle(t, above, above_count, *s);
  }
}

}  // namespace

CutFaces cut_and_weld(const Complex& m, int axis, double value, bool on_plane_is_above,
                      const std::vector<Index>& candidates, SliceStages* stages) {
  StageClock clock(stages);
  const int k = m.vertices_per_simplex();
  // Kept between this thread's slices: their buffers' memory is then warm in the caches.
  // (A reference, so that OpenMP's threads share this thread's chunks.)
  thread_local std::vector<Chunk> kept_chunks;
  std::vector<Chunk>& chunks = kept_chunks;
  chunks.resize((candidates.size() + kChunk - 1) / kChunk);
  for (Chunk& chunk : chunks) chunk.keys.clear(), chunk.corners.clear(), chunk.simplex.clear();
  const std::ptrdiff_t chunk_count = static_cast<std::ptrdiff_t>(chunks.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count()) if (chunk_count > 1)
  for (std::ptrdiff_t c = 0; c < chunk_count; ++c) {
    const Index* begin = candidates.data() + c * kChunk;
    cut_chunk(m, axis, value, on_plane_is_above, begin, std::min(begin + kChunk, candidates.data() + candidates.size()),
              chunks[c]);
  }
  clock.lap(&SliceStages::cut);
  CutFaces out;
  out.n = k - 1;
  std::vector<std::span<const std::uint64_t>> keys;
  std::vector<std::span<Index>> ids;
  for (Chunk& chunk : chunks) {
    chunk.ids.resize(chunk.keys.size());
    keys.emplace_back(chunk.keys), ids.emplace_back(chunk.ids);
  }
  weld(m, axis, value, keys, ids, out.points);
  out.on_vertices = std::any_of(out.points.begin(), out.points.end(), [](const Point& p) { return p.a == p.b; });

  std::vector<size_t> first_face(chunks.size() + 1, 0);
  for (size_t c = 0; c < chunks.size(); ++c) first_face[c + 1] = first_face[c] + chunks[c].simplex.size();
  out.corners.resize(first_face.back() * out.n);
  out.simplex.resize(first_face.back());
#pragma omp parallel for schedule(static) num_threads(thread_count()) if (chunk_count > 1)
  for (std::ptrdiff_t c = 0; c < chunk_count; ++c) {
    const Chunk& chunk = chunks[c];
    std::copy(chunk.simplex.begin(), chunk.simplex.end(), out.simplex.begin() + first_face[c]);
    Index* corner = out.corners.data() + first_face[c] * out.n;
    for (const Index position : chunk.corners) *corner++ = chunk.ids[position];
  }
  clock.lap(&SliceStages::weld);
  return out;
}

void cancel_opposite_pairs(CutFaces& faces) {
  const int n = faces.n;
  const size_t count = faces.simplex.size();
  // A slit closes up only where the plane passes through manifold vertices
  // (a keyframe, the end of a morph); elsewhere its two sides are apart.
  // Only faces whose corners are all manifold vertices can cancel.
  const auto& cut = faces.points;
  auto on_vertices = [&](size_t f) {
    for (int c = 0; c < n; ++c) {
      const auto& p = cut[faces.corners[f * n + c]];
      if (p.a != p.b) return false;
    }
    return true;
  };
  size_t eligible = 0;
  for (size_t f = 0; f < count; ++f) eligible += on_vertices(f);
  if (eligible < 2) return;
  // Each face's sorted vertex set goes into an open-addressing table; a face
  // meeting a live face with the same set and the opposite orientation
  // cancels with it. One probe per face.
  std::vector<std::array<Index, 3>> sorted(count);
  std::vector<signed char> parity(count);
  size_t capacity = 16;
  while (capacity < 2 * eligible + 16) capacity <<= 1;
  std::vector<std::int64_t> table(capacity, -1);
  std::vector<bool> drop(count, false);
  bool any = false;
  for (size_t f = 0; f < count; ++f) {
    if (!on_vertices(f)) continue;
    std::array<Index, 3>& key = sorted[f];
    key = {-1, -1, -1};
    std::copy(faces.corners.begin() + f * n, faces.corners.begin() + (f + 1) * n, key.begin());
    parity[f] = static_cast<signed char>(n == 2 ? (key[0] < key[1] ? 1 : -1) : permutation_parity(key.data(), n));
    std::sort(key.begin(), key.begin() + n);
    std::uint64_t h = 1469598103934665603ull;
    for (int c = 0; c < n; ++c) h = (h ^ static_cast<std::uint32_t>(key[c])) * 1099511628211ull;
    size_t slot = h & (capacity - 1);
    bool cancelled = false;
    for (; table[slot] >= 0; slot = (slot + 1) & (capacity - 1)) {
      const size_t other = static_cast<size_t>(table[slot]);
      if (!drop[other] && sorted[other] == key && parity[other] != parity[f]) {
        drop[other] = drop[f] = any = cancelled = true;
        break;
      }
    }
    if (!cancelled) table[slot] = static_cast<std::int64_t>(f);
  }
  if (!any) return;
  size_t kept = 0;
  for (size_t f = 0; f < count; ++f) {
    if (drop[f]) continue;
    std::copy(faces.corners.begin() + f * n, faces.corners.begin() + (f + 1) * n, faces.corners.begin() + kept * n);
    faces.simplex[kept++] = faces.simplex[f];
  }
  faces.corners.resize(kept * n);
  faces.simplex.resize(kept);
}

std::vector<Index> used_points(std::vector<Index>& corners, Index count) {
  std::vector<Index> renumbered(count, -1);
  for (const Index c : corners) renumbered[c] = 0;
  std::vector<Index> kept;
  kept.reserve(count);
  for (Index p = 0; p < count; ++p)
    if (renumbered[p] == 0) renumbered[p] = static_cast<Index>(kept.size()), kept.push_back(p);
  if (static_cast<Index>(kept.size()) != count)
    for (Index& c : corners) c = renumbered[c];
  return kept;
}

}  // namespace animanifold::slice_cut
