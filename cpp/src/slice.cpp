#include "animanifold/slice.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace animanifold {

namespace {

// Values this share of the manifold's extent along the axis away from a
// vertex's coordinate slice at the vertex's (see slice()).
constexpr double kSnapToVertices = 1e-12;

// How close to a vertex coordinate a value is taken as it: kSnapToVertices of
// the manifold's extent along the axis. Scaled before subtracting, so that a
// manifold from -1e308 to 1e308 has a finite tolerance, not an infinite one.
double snap_tolerance(double lowest, double highest) {
  return kSnapToVertices * highest - kSnapToVertices * lowest;
}

}  // namespace

// ---------------------------------------------------------------- interval index

IntervalIndex::IntervalIndex(const PointMatrix& V, const SimplexMatrix& S, int axis) : axis_(axis) {
  if (axis < 0 || axis >= V.cols()) fail<InputError>("axis ", axis, " is outside 0..", V.cols() - 1);
  nodes_.resize(S.rows());
  lowest_ = std::numeric_limits<double>::infinity();
  highest_ = -lowest_;
  for (Index s = 0; s < S.rows(); ++s) {
    double low = V(S(s, 0), axis), high = low;
    for (int c = 1; c < S.cols(); ++c) {
      const double x = V(S(s, c), axis);
      low = std::min(low, x);
      high = std::max(high, x);
    }
    nodes_[s] = {low, high, high, s};
    lowest_ = std::min(lowest_, low);
    highest_ = std::max(highest_, high);
  }
  std::sort(nodes_.begin(), nodes_.end(), [](const Node& a, const Node& b) {
    return a.low < b.low || (a.low == b.low && a.simplex < b.simplex);
  });
  // The tree is implicit: the root of a range [lo, hi) is its midpoint.
  // subtree_high of a root is the largest `high` in its range.
  struct Builder {
    std::vector<Node>& nodes;
    double build(size_t lo, size_t hi) {
      if (lo >= hi) return -std::numeric_limits<double>::infinity();
      const size_t mid = lo + (hi - lo) / 2;
      const double h = std::max({nodes[mid].high, build(lo, mid), build(mid + 1, hi)});
      nodes[mid].subtree_high = h;
      return h;
    }
  };
  Builder{nodes_}.build(0, nodes_.size());
  vertex_values_.assign(V.col(axis).begin(), V.col(axis).end());
  std::sort(vertex_values_.begin(), vertex_values_.end());
  vertex_values_.erase(std::unique(vertex_values_.begin(), vertex_values_.end()), vertex_values_.end());
}

std::optional<std::pair<double, double>> IntervalIndex::topology_interval(double value) const {
  // The same snap as slice(): a value it would move onto a vertex has that vertex's faces.
  const double snap = snap_tolerance(lowest_, highest_);
  const auto above = std::upper_bound(vertex_values_.begin(), vertex_values_.end(), value);
  if (above == vertex_values_.begin() || above == vertex_values_.end()) return std::nullopt;
  const double lo = *(above - 1), hi = *above;
  if (value - lo <= snap || hi - value <= snap) return std::nullopt;
  return std::make_pair(lo, hi);
}

void IntervalIndex::stab(double value, std::vector<Index>& out) const {
  // Explicit stack of ranges: depth is log2(#S) + 1.
  std::pair<size_t, size_t> stack[64];
  int top = 0;
  stack[top++] = {0, nodes_.size()};
  while (top > 0) {
    const auto [lo, hi] = stack[--top];
    if (lo >= hi) continue;
    const size_t mid = lo + (hi - lo) / 2;
    const Node& node = nodes_[mid];
    if (node.subtree_high < value) continue;  // nothing in this range reaches the value
    stack[top++] = {lo, mid};
    if (node.low <= value) {  // ranges right of mid start at or after node.low
      if (node.high >= value) out.push_back(node.simplex);
      stack[top++] = {mid + 1, hi};
    }
  }
}

size_t IntervalIndex::memory_bytes() const {
  return nodes_.size() * sizeof(Node) + vertex_values_.size() * sizeof(double);
}

// ---------------------------------------------------------------- slicing

namespace {

// Welds cut points: one slice vertex per manifold vertex or edge. The
// table is open addressing with linear probing over a power-of-two array:
// a slice makes one lookup per cut edge per simplex, so this is the inner
// loop of live playback.
class CutPoints {
 public:
  CutPoints(const Complex& m, int axis, double value, size_t expected) : m_(m), axis_(axis), value_(value) {
    size_t capacity = 16;
    while (capacity < 2 * expected + 16) capacity <<= 1;
    keys_.assign(capacity, kEmpty);
    ids_.resize(capacity);
    mask_ = capacity - 1;
    edges_.reserve(expected);
  }

  // The slice vertex where the hyperplane crosses edge (a, b); a == b for a
  // manifold vertex on the plane. Edges are keyed by (min, max) so both
  // simplices sharing an edge get the same vertex and the same coordinates.
  Index on_edge(Index a, Index b) {
    if (a > b) std::swap(a, b);
    double s = 0.0;
    if (a != b) {
      const double xa = m_.V(a, axis_), xb = m_.V(b, axis_);
      s = (value_ - xa) / (xb - xa);
      if (s <= 0.0) s = 0.0, b = a;          // the plane passes through a
      else if (s >= 1.0) s = 0.0, a = b;     // ... or through b
    }
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
                              static_cast<std::uint32_t>(b);
    size_t slot = (key * 0x9E3779B97F4A7C15ull) >> 20 & mask_;
    while (keys_[slot] != kEmpty) {
      if (keys_[slot] == key) return ids_[slot];
      slot = (slot + 1) & mask_;
    }
    if (edges_.size() * 2 + 2 > keys_.size()) grow();
    return insert(key, {a, b, s});
  }

  struct Cut {
    Index a, b;
    double s;
  };
  const std::vector<Cut>& cuts() const { return edges_; }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  Index insert(std::uint64_t key, const Cut& cut) {
    size_t slot = (key * 0x9E3779B97F4A7C15ull) >> 20 & mask_;
    while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
    keys_[slot] = key;
    ids_[slot] = static_cast<Index>(edges_.size());
    edges_.push_back(cut);
    return ids_[slot];
  }

  void grow() {
    std::vector<Cut> cuts = std::move(edges_);
    edges_.clear();
    keys_.assign(keys_.size() * 2, kEmpty);
    ids_.resize(keys_.size());
    mask_ = keys_.size() - 1;
    edges_.reserve(cuts.size() * 2);
    for (const Cut& c : cuts)
      insert((static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.a)) << 32) | static_cast<std::uint32_t>(c.b), c);
  }

  const Complex& m_;
  int axis_;
  double value_;
  std::vector<std::uint64_t> keys_;
  std::vector<Index> ids_;
  size_t mask_ = 0;
  std::vector<Cut> edges_;
};

struct FaceSink {
  std::vector<Index> corners;  // n per face
  std::vector<Index> simplex;
  int n;
  void add(const Index* ids, Index source) {
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (ids[a] == ids[b]) return;  // collapsed: zero area
    corners.insert(corners.end(), ids, ids + n);
    simplex.push_back(source);
  }
};

// A face and its exact reverse on the same vertices bound nothing: they are
// the two sides of a zero-width slit (where a manifold that opens a hole or a
// split right after this time is cut at that time). Cancel such pairs so the
// slice is the limit surface, not the slit.
void cancel_opposite_pairs(FaceSink& faces, const CutPoints& cuts) {
  const int n = faces.n;
  const size_t count = faces.simplex.size();
  // A slit closes up only where the plane passes through manifold vertices
  // (a keyframe, the end of a morph); elsewhere its two sides are apart.
  // Only faces whose corners are all manifold vertices can cancel.
  const auto& cut = cuts.cuts();
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

// The cut points that `corners` use, in order, with `corners` renumbered
// onto them (all of 0..count-1, untouched, when every point is used).
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

// Tets in R^4 → triangles in R^3 (Figure 2.6).
void cut_tet(const Index* t, const bool* above, int above_count, Index source, CutPoints& cuts, FaceSink& faces) {
  Index f[3];
  if (above_count == 1 || above_count == 3) {
    // The lone vertex and the opposite facet in its outward orientation.
    int apex = 0;
    while (above[apex] != (above_count == 1)) ++apex;
    facet(t, 4, apex, f);
    Index tri[3] = {cuts.on_edge(t[apex], f[0]), cuts.on_edge(t[apex], f[1]), cuts.on_edge(t[apex], f[2])};
    if (above_count == 3) std::swap(tri[0], tri[1]);  // the part above lies away from the apex
    faces.add(tri, source);
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
  const Index ik = cuts.on_edge(up[0], down[0]), il = cuts.on_edge(up[0], down[1]);
  const Index jl = cuts.on_edge(up[1], down[1]), jk = cuts.on_edge(up[1], down[0]);
  Index a[3] = {ik, il, jl}, b[3] = {ik, jl, jk};
  faces.add(a, source);
  faces.add(b, source);
}

// Triangles in R^3 → segments in R^2.
void cut_triangle(const Index* t, const bool* above, int above_count, Index source, CutPoints& cuts,
                  FaceSink& faces) {
  int apex = 0;
  while (above[apex] != (above_count == 1)) ++apex;
  Index f[2];
  facet(t, 3, apex, f);
  Index seg[2] = {cuts.on_edge(t[apex], f[0]), cuts.on_edge(t[apex], f[1])};
  if (above_count == 2) std::swap(seg[0], seg[1]);
  faces.add(seg, source);
}

}  // namespace

namespace {

void check_slice_request(const Complex& m, int axis, double value, const IntervalIndex* index) {
  const int D = m.ambient_dimension();
  const int k = m.vertices_per_simplex();
  if (k != D || (D != 3 && D != 4))
    fail<InputError>("slicing needs tets in R^4 or triangles in R^3; got ", k, "-vertex simplices in R^", D);
  if (axis < 0 || axis >= D) fail<InputError>("slicing axis ", axis, " is outside 0..", D - 1);
  if (!std::isfinite(value)) fail<InputError>("slicing value is not finite");
  if (index && (index->axis() != axis))
    fail<InputError>("interval index was built for axis ", index->axis(), ", not ", axis);
}

// The simplices a hyperplane may cut, found through the index or by a scan.
class Stabber {
 public:
  Stabber(const Complex& m, int axis, const IntervalIndex* index) : m_(m), axis_(axis), index_(index) {
    if (index) {
      lowest = index->lowest(), highest = index->highest();
    } else {
      lowest = m.V.rows() ? m.V.col(axis).minCoeff() : 0.0;
      highest = m.V.rows() ? m.V.col(axis).maxCoeff() : 0.0;
    }
  }

  // The simplices whose extent along the axis holds `at`, into `candidates`.
  void stab(double at, std::vector<Index>& candidates) const {
    candidates.clear();
    if (index_) {
      index_->stab(at, candidates);
      return;
    }
    const int k = m_.vertices_per_simplex();
    candidates.reserve(1024);
    for (Index s = 0; s < m_.S.rows(); ++s) {
      double low = m_.V(m_.S(s, 0), axis_), high = low;
      for (int c = 1; c < k; ++c) {
        const double x = m_.V(m_.S(s, c), axis_);
        low = std::min(low, x), high = std::max(high, x);
      }
      if (low <= at && at <= high) candidates.push_back(s);
    }
  }

  double lowest, highest;

 private:
  const Complex& m_;
  int axis_;
  const IntervalIndex* index_;
};

// A value a rounding away from vertices (a frame's time computed as
// t0 + k·dt next to a keyframe, or a layer of a morph) is taken as theirs:
// cut a hair off them, edges from each vertex would give slice vertices
// of their own within an ulp of it, and faces between them that fold.
// Just outside the manifold's ends, the ends' own. Returns the value cut at,
// with `candidates` the simplices that may cut there.
double snapped_value(const Complex& m, int axis, double value, const Stabber& stabber,
                     std::vector<Index>& candidates) {
  const int k = m.vertices_per_simplex();
  const double snap = snap_tolerance(stabber.lowest, stabber.highest);
  if (value < stabber.lowest && stabber.lowest - value <= snap) value = stabber.lowest;
  if (value > stabber.highest && value - stabber.highest <= snap) value = stabber.highest;
  stabber.stab(value, candidates);
  double nearest = value, distance = std::numeric_limits<double>::infinity();
  for (const Index s : candidates)
    for (int c = 0; c < k; ++c) {
      const double x = m.V(m.S(s, c), axis), d = std::abs(x - value);
      if (d <= snap && d < distance) nearest = x, distance = d;
    }
  if (nearest != value) value = nearest, stabber.stab(value, candidates);
  return value;
}

// Each candidate cut by the hyperplane: its faces into `faces`, their
// corners welded in `cuts`. On-plane vertices count as below, except at the
// very top of the manifold.
void cut_candidates(const Complex& m, int axis, double value, bool on_plane_is_above,
                    const std::vector<Index>& candidates, CutPoints& cuts, FaceSink& faces) {
  const int k = m.vertices_per_simplex();
  bool above[4];
  for (const Index s : candidates) {
    const Index* t = m.S.row(s).data();
    int above_count = 0;
    for (int c = 0; c < k; ++c) {
      const double x = m.V(t[c], axis);
      above[c] = on_plane_is_above ? x >= value : x > value;
      above_count += above[c];
    }
    if (above_count == 0 || above_count == k) continue;
    if (k == 4) cut_tet(t, above, above_count, s, cuts, faces);
    else cut_triangle(t, above, above_count, s, cuts, faces);
  }
}

// The frame from its welded cut points and faces: coordinates other than
// `axis`, attributes interpolated along the cut edges (inherited by faces).
Slice frame_of_cuts(const Complex& m, int axis, const CutPoints& cuts, FaceSink& faces) {
  const int D = m.ambient_dimension();
  const int k = m.vertices_per_simplex();
  // Only the cut points that corners of the frame use: on a vertex plane,
  // a simplex whose faces there are degenerate (or cancelled) registers its
  // corners too, and where the manifold holds copies of a vertex (split at a
  // UV seam) those copies would be left loose in the frame.
  const auto& all_cuts = cuts.cuts();
  std::vector<Index> kept = used_points(faces.corners, static_cast<Index>(all_cuts.size()));
  const Index P = static_cast<Index>(kept.size());
  auto cut_at = [&](Index p) -> const auto& { return all_cuts[kept[p]]; };

  Slice out;
  out.vertices.resize(P, D - 1);
  out.vertex_edges.resize(P, 2);
  out.edge_parameter.resize(P);
  for (Index p = 0; p < P; ++p) {
    const auto& c = cut_at(p);
    out.vertex_edges(p, 0) = c.a, out.vertex_edges(p, 1) = c.b;
    out.edge_parameter(p) = c.s;
    for (int d = 0, o = 0; d < D; ++d) {
      if (d == axis) continue;
      // A vertex on the plane is copied, never interpolated: keyframes come back exactly.
      out.vertices(p, o++) = c.a == c.b ? m.V(c.a, d) : (1.0 - c.s) * m.V(c.a, d) + c.s * m.V(c.b, d);
    }
  }
  const Index F = static_cast<Index>(faces.simplex.size());
  out.faces = Eigen::Map<const SimplexMatrix>(faces.corners.data(), F, k - 1);
  out.face_simplex = Eigen::Map<const IndexVector>(faces.simplex.data(), F);

  for (const auto& [name, table] : m.vertex_attributes) {
    PointMatrix values(P, table.cols());
    for (Index p = 0; p < P; ++p) {
      const auto& c = cut_at(p);
      values.row(p) = c.a == c.b ? table.row(c.a) : ((1.0 - c.s) * table.row(c.a) + c.s * table.row(c.b)).eval();
    }
    out.vertex_attributes[name] = std::move(values);
  }
  for (const auto& [name, table] : m.simplex_attributes) {
    SimplexMatrix values(F, table.cols());
    for (Index f = 0; f < F; ++f) values.row(f) = table.row(out.face_simplex(f));
    out.face_attributes[name] = std::move(values);
  }
  return out;
}

}  // namespace

Slice slice(const Complex& m, int axis, double value, const IntervalIndex* index) {
  check_slice_request(m, axis, value, index);
  const int D = m.ambient_dimension();
  const int k = m.vertices_per_simplex();
  const Stabber stabber(m, axis, index);
  std::vector<Index> candidates;
  value = snapped_value(m, axis, value, stabber, candidates);

  CutPoints cuts(m, axis, value, candidates.size() * 2);
  FaceSink faces{{}, {}, k - 1};
  faces.corners.reserve(candidates.size() * 2 * (k - 1));
  cut_candidates(m, axis, value, value >= stabber.highest, candidates, cuts, faces);
  cancel_opposite_pairs(faces, cuts);
  Slice out = frame_of_cuts(m, axis, cuts, faces);

  // Dropping coordinate `axis` instead of the last one permutes the remaining
  // coordinates' orientation by (-1)^(D-1-axis): the table's faces would then
  // face inward, so they are turned over. Slices along time are never
  // turned, so keyframes keep their orientation.
  if ((D - 1 - axis) % 2 == 1) out.faces.col(0).swap(out.faces.col(1));
  out.normals = frame_vertex_normals(out.vertices, out.faces);
  return out;
}

}  // namespace animanifold

namespace animanifold {

Slicer::Slicer(std::shared_ptr<const Complex> manifold) : manifold_(std::move(manifold)) {
  if (!manifold_) fail<InputError>("Slicer needs a manifold");
  indices_.resize(manifold_->ambient_dimension());
  index_built_ = std::make_unique<std::once_flag[]>(indices_.size());
}

const IntervalIndex& Slicer::index(int axis) {
  if (axis < 0 || axis >= static_cast<int>(indices_.size()))
    fail<InputError>("slicing axis ", axis, " is outside 0..", indices_.size() - 1);
  // Threads slicing a fresh manifold at once (the bindings release the GIL)
  // would otherwise each build the index and replace one another's while in use.
  std::call_once(index_built_[axis], [&] {
    indices_[axis] = std::make_unique<IntervalIndex>(manifold_->V, manifold_->S, axis);
  });
  return *indices_[axis];
}

Slice Slicer::slice(int axis, double value, bool use_index) {
  return animanifold::slice(*manifold_, axis, value, use_index ? &index(axis) : nullptr);
}

}  // namespace animanifold
