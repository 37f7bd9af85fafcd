// Tetrahedral (and triangular) smoothing subdivision of animation manifolds:
// Schaefer, Hakenberg & Warren 2004. See subdivide.hpp for the scheme.
#include "animanifold/subdivide.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/memory_estimates.hpp"
#include "animanifold/threads.hpp"
#include "subdivision_shared.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace animanifold {

ManifoldScheme parse_manifold_scheme(const std::string& name) {
  return parse_name(name, kManifoldSchemeNames, "manifold subdivision scheme");
}

namespace {

using namespace subdivision_detail;

// ---------------------------------------------------------------------------
// Refinement tables, derived once from canonical reference cells so that every
// child's orientation is checked by a determinant instead of by hand.
//
// Tetrahedron slots: 0..3 its vertices, 4..9 the midpoints of its edges in the
// order of kTetEdges. Octahedron slots: 0..5 its vertices, stored as three
// opposite pairs (0,1), (2,3), (4,5); 6..17 the midpoints of its edges in the
// order of Tables::oct_edges; 18 its centre. An octahedron is positively
// oriented when det(v1-v0, v3-v2, v5-v4) > 0 in reference coordinates, as is
// the canonical one with vertices -x, +x, -y, +y, -z, +z. Triangle slots: 0..2
// vertices, 3..5 midpoints of edges (0,1), (0,2), (1,2).

constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kTriEdges[3][2] = {{0, 1}, {0, 2}, {1, 2}};

using Vec3 = Eigen::Vector3d;

double det3(const Vec3& a, const Vec3& b, const Vec3& c) {
  Eigen::Matrix3d m;
  m.row(0) = a;
  m.row(1) = b;
  m.row(2) = c;
  return m.determinant();
}

struct Tables {
  std::array<std::array<int, 4>, 4> tet_corner{};  // tet -> 4 corner tets
  std::array<int, 6> tet_oct{};                     // tet -> the inner octahedron
  std::array<std::array<int, 2>, 12> oct_edges{};
  std::array<std::array<int, 6>, 6> oct_corner{};  // oct -> 6 corner octs
  std::array<std::array<int, 4>, 8> oct_tet{};     // oct -> 8 tets around the centre
  std::array<std::array<std::array<int, 4>, 4>, 3> oct_cut{};  // oct -> 4 tets along diagonal p
  std::array<std::array<int, 3>, 4> tri_children{};

  Tables() {
    // --- tetrahedron
    std::array<Vec3, 10> t;
    t[0] = Vec3(0, 0, 0);
    t[1] = Vec3(1, 0, 0);
    t[2] = Vec3(0, 1, 0);
    t[3] = Vec3(0, 0, 1);
    for (int e = 0; e < 6; ++e) t[4 + e] = (t[kTetEdges[e][0]] + t[kTetEdges[e][1]]) / 2;
    auto tet_mid = [](int a, int b) {
      for (int e = 0; e < 6; ++e)
        if ((kTetEdges[e][0] == a && kTetEdges[e][1] == b) || (kTetEdges[e][0] == b && kTetEdges[e][1] == a))
          return 4 + e;
      return -1;
    };
    auto orient_tet = [](std::array<int, 4>& s, auto& coords) {
      if (det3(coords[s[1]] - coords[s[0]], coords[s[2]] - coords[s[0]], coords[s[3]] - coords[s[0]]) < 0)
        std::swap(s[0], s[1]);
    };
    auto orient_oct = [](std::array<int, 6>& s, auto& coords) {
      if (det3(coords[s[1]] - coords[s[0]], coords[s[3]] - coords[s[2]], coords[s[5]] - coords[s[4]]) < 0)
        std::swap(s[0], s[1]);
    };
    for (int i = 0; i < 4; ++i) {
      std::array<int, 4> c{};
      for (int j = 0; j < 4; ++j) c[j] = (j == i) ? i : tet_mid(i, j);
      orient_tet(c, t);
      tet_corner[i] = c;
    }
    tet_oct = {tet_mid(0, 1), tet_mid(2, 3), tet_mid(0, 2), tet_mid(1, 3), tet_mid(0, 3), tet_mid(1, 2)};
    orient_oct(tet_oct, t);

    // --- octahedron
    std::array<Vec3, 19> o;
    for (int a = 0; a < 3; ++a) {
      o[2 * a] = -Vec3::Unit(a);
      o[2 * a + 1] = Vec3::Unit(a);
    }
    int e = 0;
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b)
        if (a / 2 != b / 2) oct_edges[e++] = {a, b};
    for (e = 0; e < 12; ++e) o[6 + e] = (o[oct_edges[e][0]] + o[oct_edges[e][1]]) / 2;
    o[18] = Vec3::Zero();
    auto oct_mid = [this](int a, int b) {
      for (int f = 0; f < 12; ++f)
        if ((oct_edges[f][0] == a && oct_edges[f][1] == b) || (oct_edges[f][0] == b && oct_edges[f][1] == a))
          return 6 + f;
      return -1;
    };
    for (int v = 0; v < 6; ++v) {
      std::array<int, 6> c{};
      c[0] = v;
      c[1] = 18;
      int k = 2;
      for (int axis = 0; axis < 3; ++axis) {
        if (axis == v / 2) continue;
        c[k++] = oct_mid(v, 2 * axis);
        c[k++] = oct_mid(v, 2 * axis + 1);
      }
      orient_oct(c, o);
      oct_corner[v] = c;
    }
    int f = 0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) {
          const int a = i, b = 2 + j, c = 4 + k;
          std::array<int, 4> s = {oct_mid(a, b), oct_mid(b, c), oct_mid(a, c), 18};
          orient_tet(s, o);
          oct_tet[f++] = s;
        }
    for (int p = 0; p < 3; ++p) {
      const int q = (p + 1) % 3, r = (p + 2) % 3;
      const std::array<int, 4> ring = {2 * q, 2 * r, 2 * q + 1, 2 * r + 1};
      for (int i = 0; i < 4; ++i) {
        std::array<int, 4> s = {2 * p, 2 * p + 1, ring[i], ring[(i + 1) % 4]};
        orient_tet(s, o);
        oct_cut[p][i] = s;
      }
    }

    // --- triangle
    std::array<Eigen::Vector2d, 6> r;
    r[0] = {0, 0};
    r[1] = {1, 0};
    r[2] = {0, 1};
    for (int g = 0; g < 3; ++g) r[3 + g] = (r[kTriEdges[g][0]] + r[kTriEdges[g][1]]) / 2;
    tri_children = {{{0, 3, 4}, {3, 1, 5}, {4, 5, 2}, {3, 5, 4}}};
    for (auto& s : tri_children) {
      const Eigen::Vector2d u = r[s[1]] - r[s[0]], w = r[s[2]] - r[s[0]];
      if (u.x() * w.y() - u.y() * w.x() < 0) std::swap(s[0], s[1]);
    }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

// ---------------------------------------------------------------------------
// Unique edges of a level, in (min, max) order: the CSR of each vertex's
// larger neighbours. Edge ids are positions in that order.
class EdgeTable {
 public:
  template <class ForEachEdge>
  EdgeTable(Index vertex_count, ForEachEdge for_each_edge) {
    offsets_.assign(static_cast<size_t>(vertex_count) + 1, 0);
    for_each_edge([&](Index a, Index b) { ++offsets_[static_cast<size_t>(std::min(a, b)) + 1]; });
    for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) offsets_[v + 1] += offsets_[v];
    others_.resize(offsets_.back());
    {
      std::vector<std::int64_t> fill(offsets_.begin(), offsets_.end() - 1);
      for_each_edge([&](Index a, Index b) { others_[fill[std::min(a, b)]++] = std::max(a, b); });
    }
    std::int64_t write = 0;
    for (size_t v = 0; v < static_cast<size_t>(vertex_count); ++v) {
      const std::int64_t begin = offsets_[v], end = offsets_[v + 1];
      std::sort(others_.begin() + begin, others_.begin() + end);
      const auto last = std::unique(others_.begin() + begin, others_.begin() + end);
      offsets_[v] = write;
      for (auto it = others_.begin() + begin; it != last; ++it) others_[write++] = *it;
    }
    offsets_.back() = write;
    others_.resize(write);
    others_.shrink_to_fit();
  }

  std::int64_t size() const { return static_cast<std::int64_t>(others_.size()); }

  Index find(Index a, Index b) const {
    if (a > b) std::swap(a, b);
    const auto first = others_.begin() + offsets_[a], last = others_.begin() + offsets_[a + 1];
    const auto it = std::lower_bound(first, last, b);
    return static_cast<Index>(it - others_.begin());  // (a, b) is always present
  }

  // Visits (id, a, b) for every edge, on all threads: `visit` may write only to slots of its edge id.
  template <class Visit>
  void for_each(Visit visit) const {
    const std::int64_t vertex_count = static_cast<std::int64_t>(offsets_.size()) - 1;
#pragma omp parallel for schedule(static) num_threads(thread_count())
    for (std::int64_t v = 0; v < vertex_count; ++v)
      for (std::int64_t i = offsets_[v]; i < offsets_[v + 1]; ++i) visit(static_cast<Index>(i), static_cast<Index>(v), others_[i]);
  }

 private:
  std::vector<std::int64_t> offsets_;
  std::vector<Index> others_;
};

// One level of the hybrid mesh with its boundary features.
struct Level {
  PointMatrix X;                 // #V by C: positions (first D columns), then vertex attributes
  int k = 4;                     // vertices per simplex: 4 tets, 3 triangles
  std::vector<Index> simplices;  // stride k
  std::vector<Index> simplex_root;
  std::vector<std::array<Index, 6>> octs;  // only when k == 4
  std::vector<Index> oct_root;
  // Boundary facets (stride k-1) with their patch: index of their keyframe
  // time, or -1 for the side patch.
  std::vector<Index> boundary;
  std::vector<int> boundary_patch;
  // Creases: where boundary patches meet. Segments (stride 2) when k == 4;
  // fixed points when k == 3.
  std::vector<Index> creases;
  std::vector<Index> corners;    // fixed points where creases meet (k == 4)
  std::vector<int> keyframe;     // per vertex: index of the keyframe time it lies on, or -1
  SimplexMatrix parents;         // #V by 2, relative to the previous level
};

constexpr Index kMaxIndex = std::numeric_limits<Index>::max();

// The next level's points: the old ones, the midpoint of every edge (after
// them, in the edge table's order), then the centre of every octahedron;
// with their keyframes and parents.
void refine_points(const Level& L, const EdgeTable& edges, Level& N) {
  const Index V = static_cast<Index>(L.X.rows());
  const std::int64_t E = edges.size();
  const size_t O = L.octs.size();
  const std::int64_t newV = static_cast<std::int64_t>(V) + E + static_cast<std::int64_t>(O);
  if (newV > kMaxIndex) fail<InputError>("subdivision would create ", newV, " vertices, more than 32-bit indices hold");
  const Eigen::Index C = L.X.cols();
  N.X.resize(newV, C);
  N.X.topRows(V) = L.X;
  N.keyframe.resize(newV);
  std::copy(L.keyframe.begin(), L.keyframe.end(), N.keyframe.begin());
  N.parents.resize(newV, 2);
  for (Index v = 0; v < V; ++v) N.parents.row(v) << v, v;
  edges.for_each([&](Index id, Index a, Index b) {
    const Index m = V + id;
    N.X.row(m) = (L.X.row(a) + L.X.row(b)) * 0.5;
    N.keyframe[m] = L.keyframe[a] == L.keyframe[b] ? L.keyframe[a] : -1;
    N.parents.row(m) << a, b;
  });
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (size_t o = 0; o < O; ++o) {
    const Index m = static_cast<Index>(V + E + static_cast<std::int64_t>(o));
    const auto& c = L.octs[o];
    N.X.row(m).setZero();
    int key = L.keyframe[c[0]];
    for (int i = 0; i < 6; ++i) {
      N.X.row(m) += L.X.row(c[i]);
      if (L.keyframe[c[i]] != key) key = -1;
    }
    N.X.row(m) /= 6.0;
    N.keyframe[m] = key;
    N.parents.row(m) << -1, -1;
  }
}

// The midpoint of edge (a, b) in the next level.
struct Midpoints {
  const EdgeTable& edges;
  Index V;
  Index operator()(Index a, Index b) const { return V + edges.find(a, b); }
};

// Tetrahedra split into four corner tetrahedra and an octahedron,
// octahedra into six corner octahedra and eight tetrahedra around the centre.
// Children are laid out by their parent's index (tetrahedra's children
// first), so every parent writes its own rows and the result is the same for
// any thread count.
void refine_tetrahedral_cells(const Level& L, const Midpoints& mid, Level& N) {
  const Tables& T = tables();
  const size_t S = L.simplices.size() / 4;
  const size_t O = L.octs.size();
  const std::int64_t E = mid.edges.size();
  N.simplices.resize((4 * S + 8 * O) * 4);
  N.simplex_root.resize(4 * S + 8 * O);
  N.octs.resize(S + 6 * O);
  N.oct_root.resize(S + 6 * O);
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (size_t s = 0; s < S; ++s) {
    const Index* c = &L.simplices[s * 4];
    Index slot[10];
    for (int i = 0; i < 4; ++i) slot[i] = c[i];
    for (int e = 0; e < 6; ++e) slot[4 + e] = mid(c[kTetEdges[e][0]], c[kTetEdges[e][1]]);
    for (size_t j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) N.simplices[(4 * s + j) * 4 + i] = slot[T.tet_corner[j][i]];
      N.simplex_root[4 * s + j] = L.simplex_root[s];
    }
    for (int i = 0; i < 6; ++i) N.octs[s][i] = slot[T.tet_oct[i]];
    N.oct_root[s] = L.simplex_root[s];
  }
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (size_t o = 0; o < O; ++o) {
    const auto& c = L.octs[o];
    Index slot[19];
    for (int i = 0; i < 6; ++i) slot[i] = c[i];
    for (int e = 0; e < 12; ++e) slot[6 + e] = mid(c[T.oct_edges[e][0]], c[T.oct_edges[e][1]]);
    slot[18] = static_cast<Index>(mid.V + E + static_cast<std::int64_t>(o));
    for (size_t j = 0; j < 6; ++j) {
      for (int i = 0; i < 6; ++i) N.octs[S + 6 * o + j][i] = slot[T.oct_corner[j][i]];
      N.oct_root[S + 6 * o + j] = L.oct_root[o];
    }
    for (size_t j = 0; j < 8; ++j) {
      const size_t row = 4 * S + 8 * o + j;
      for (int i = 0; i < 4; ++i) N.simplices[row * 4 + i] = slot[T.oct_tet[j][i]];
      N.simplex_root[row] = L.oct_root[o];
    }
  }
}

// Triangles split into four.
void refine_triangle_cells(const Level& L, const Midpoints& mid, Level& N) {
  const Tables& T = tables();
  const size_t S = L.simplices.size() / 3;
  N.simplices.resize(4 * S * 3);
  N.simplex_root.resize(4 * S);
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (size_t s = 0; s < S; ++s) {
    const Index* c = &L.simplices[s * 3];
    const Index slot[6] = {c[0], c[1], c[2], mid(c[0], c[1]), mid(c[0], c[2]), mid(c[1], c[2])};
    for (size_t j = 0; j < 4; ++j) {
      for (int i = 0; i < 3; ++i) N.simplices[(4 * s + j) * 3 + i] = slot[T.tri_children[j][i]];
      N.simplex_root[4 * s + j] = L.simplex_root[s];
    }
  }
}

// Boundary features: facets split like their cells, creases like edges.
void refine_boundary(const Level& L, const Midpoints& mid, Level& N) {
  const Tables& T = tables();
  const int f = L.k - 1;
  const size_t B = L.boundary.size() / f;
  for (size_t b = 0; b < B; ++b) {
    const Index* c = &L.boundary[b * f];
    if (f == 3) {
      const Index slot[6] = {c[0], c[1], c[2], mid(c[0], c[1]), mid(c[0], c[2]), mid(c[1], c[2])};
      for (const auto& child : T.tri_children) {
        for (int i = 0; i < 3; ++i) N.boundary.push_back(slot[child[i]]);
        N.boundary_patch.push_back(L.boundary_patch[b]);
      }
    } else {
      const Index m = mid(c[0], c[1]);
      N.boundary.insert(N.boundary.end(), {c[0], m, m, c[1]});
      N.boundary_patch.insert(N.boundary_patch.end(), 2, L.boundary_patch[b]);
    }
  }
  if (L.k == 4) {
    for (size_t i = 0; i + 1 < L.creases.size(); i += 2) {
      const Index a = L.creases[i], b = L.creases[i + 1], m = mid(a, b);
      N.creases.insert(N.creases.end(), {a, m, m, b});
    }
  } else {
    N.creases = L.creases;
  }
  N.corners = L.corners;
}

Level refine(const Level& L) {
  const Tables& T = tables();
  const int k = L.k;
  const Index V = static_cast<Index>(L.X.rows());
  const size_t S = L.simplices.size() / k;
  EdgeTable edges(V, [&](auto emit) {
    for (size_t s = 0; s < S; ++s) {
      const Index* c = &L.simplices[s * k];
      for (int a = 0; a < k; ++a)
        for (int b = a + 1; b < k; ++b) emit(c[a], c[b]);
    }
    for (const auto& o : L.octs)
      for (const auto& e : T.oct_edges) emit(o[e[0]], o[e[1]]);
  });
  Level N;
  N.k = k;
  refine_points(L, edges, N);
  const Midpoints mid{edges, V};
  if (k == 4) refine_tetrahedral_cells(L, mid, N);
  else refine_triangle_cells(L, mid, N);
  refine_boundary(L, mid, N);
  return N;
}

// Area-weighted normals (unnormalised) of a hypersurface level (D == k):
// tetrahedra in R^4 by the wedge product of their edges, octahedra through
// their cut into four tetrahedra, triangles in R^3 by the cross product.
PointMatrix hypersurface_normals(const Level& L, int D) {
  const Tables& T = tables();
  PointMatrix N = PointMatrix::Zero(L.X.rows(), D);
  auto add = [&](const Index* c) {
    if (D == 4) {
      Eigen::Matrix<double, 3, 4> e;
      for (int i = 0; i < 3; ++i) e.row(i) = L.X.row(c[i + 1]).head(4) - L.X.row(c[0]).head(4);
      Eigen::RowVector4d n;
      for (int j = 0; j < 4; ++j) {
        Eigen::Matrix3d minor;
        int col = 0;
        for (int m = 0; m < 4; ++m)
          if (m != j) minor.col(col++) = e.col(m);
        n(j) = ((j % 2) ? -1.0 : 1.0) * minor.determinant();
      }
      for (int i = 0; i < 4; ++i) N.row(c[i]) += n;
    } else {
      const Eigen::Vector3d a = L.X.row(c[0]).head(3).transpose();
      const Eigen::Vector3d n = (Eigen::Vector3d(L.X.row(c[1]).head(3).transpose()) - a)
                                    .cross(Eigen::Vector3d(L.X.row(c[2]).head(3).transpose()) - a);
      for (int i = 0; i < 3; ++i) N.row(c[i]) += n.transpose();
    }
  };
  for (size_t s = 0; s + L.k <= L.simplices.size(); s += L.k) add(&L.simplices[s]);
  for (const auto& o : L.octs)
    for (const auto& child : T.oct_cut[0]) {
      const Index c[4] = {o[child[0]], o[child[1]], o[child[2]], o[child[3]]};
      add(c);
    }
  return N;
}

// The averaging step. `times` are the keyframe times; `D` the number of
// coordinate columns of X (time is column D-1).
void average(Level& L, int D, const std::vector<double>& times, bool keep_keyframe_times) {
  const int k = L.k;
  const Index V = static_cast<Index>(L.X.rows());
  const Eigen::Index C = L.X.cols();
  // 3 interior, 2 boundary, 1 crease, 0 fixed.
  std::vector<std::int8_t> kind(V, 3);
  const int f = k - 1;
  for (Index v : L.boundary) kind[v] = 2;
  for (Index v : L.creases) kind[v] = (k == 4) ? 1 : 0;
  for (Index v : L.corners) kind[v] = 0;

  PointMatrix sum = PointMatrix::Zero(V, C);
  std::vector<std::int32_t> count(V, 0);
  Eigen::RowVectorXd cell(C);

  // Masks written as a*x_v + b*(sum over the cell) (+ c*x_opposite for octahedra).
  auto accumulate_simplices = [&](const std::vector<Index>& cells, int stride, int want, double self, double all) {
    const size_t n = cells.size() / stride;
    for (size_t s = 0; s < n; ++s) {
      const Index* c = &cells[s * stride];
      bool any = false;
      for (int i = 0; i < stride; ++i) any |= kind[c[i]] == want;
      if (!any) continue;
      cell.setZero();
      for (int i = 0; i < stride; ++i) cell += L.X.row(c[i]);
      for (int i = 0; i < stride; ++i) {
        const Index v = c[i];
        if (kind[v] != want) continue;
        sum.row(v) += self * L.X.row(v) + all * cell;
        ++count[v];
      }
    }
  };
  if (k == 4) {
    // Tetrahedron: -1/16 x_v + 17/48 (others) = -5/12 x_v + 17/48 (all four).
    accumulate_simplices(L.simplices, 4, 3, -5.0 / 12.0, 17.0 / 48.0);
    // Octahedron: 3/8 x_v + 1/12 (4 neighbours) + 7/24 x_opposite
    //           = 7/24 x_v + 1/12 (all six) + 5/24 x_opposite.
    for (const auto& o : L.octs) {
      bool any = false;
      for (int i = 0; i < 6; ++i) any |= kind[o[i]] == 3;
      if (!any) continue;
      cell.setZero();
      for (int i = 0; i < 6; ++i) cell += L.X.row(o[i]);
      for (int i = 0; i < 6; ++i) {
        const Index v = o[i];
        if (kind[v] != 3) continue;
        sum.row(v) += (7.0 / 24.0) * L.X.row(v) + (1.0 / 12.0) * cell + (5.0 / 24.0) * L.X.row(o[i ^ 1]);
        ++count[v];
      }
    }
    // Boundary triangles: 1/4 x_v + 3/8 (others) = -1/8 x_v + 3/8 (all three).
    accumulate_simplices(L.boundary, 3, 2, -1.0 / 8.0, 3.0 / 8.0);
    // Crease segments: 1/2 x_v + 1/2 x_other.
    accumulate_simplices(L.creases, 2, 1, 0.0, 0.5);
  } else {
    accumulate_simplices(L.simplices, 3, 3, -1.0 / 8.0, 3.0 / 8.0);
    accumulate_simplices(L.boundary, 2, 2, 0.0, 0.5);
  }
  // With keep_keyframe_times, a keyframe point that the averaging moved off
  // its hyperplane (by dt) is slid back along the manifold rather than along
  // the time axis: along u, the time axis projected onto the manifold's
  // tangent space (n the unit normal). Resetting only the time coordinate
  // would displace the point by velocity * dt, which distorts moving shapes.
  // Needs the normal of a hypersurface (D == k), taken before averaging.
  PointMatrix normals;
  const bool slide = keep_keyframe_times && D == k;
  if (slide) normals = hypersurface_normals(L, D);

#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index v = 0; v < V; ++v)
    if (count[v] > 0) L.X.row(v) = sum.row(v) / count[v];

  // Keyframe patches of the boundary stay exactly on their hyperplanes; with
  // keep_keyframe_times so does every point on a keyframe hyperplane.
  const size_t B = L.boundary.size() / f;
  for (size_t b = 0; b < B; ++b) {
    const int patch = L.boundary_patch[b];
    if (patch < 0) continue;
    for (int i = 0; i < f; ++i) L.X(L.boundary[b * f + i], D - 1) = times[patch];
  }
  if (keep_keyframe_times)
    for (Index v = 0; v < V; ++v) {
      if (L.keyframe[v] < 0) continue;
      const double target = times[L.keyframe[v]];
      const double dt = L.X(v, D - 1) - target;
      if (slide && dt != 0 && kind[v] == 3) {
        const double length = normals.row(v).norm();
        if (length > 0) {
          const Eigen::RowVectorXd n = normals.row(v) / length;
          Eigen::RowVectorXd u = -n(D - 1) * n;
          u(D - 1) += 1.0;
          // u(D-1) = 1 - n_t^2: how far the manifold is from lying in the hyperplane.
          if (u(D - 1) > 0.05) L.X.row(v).head(D) -= (dt / u(D - 1)) * u;
        }
      }
      L.X(v, D - 1) = target;
    }
}

int time_index(const std::vector<double>& times, double t) {
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  return (it != times.end() && *it == t) ? static_cast<int>(it - times.begin()) : -1;
}

void check_manifold_input(const Complex& manifold, const ManifoldSubdivisionOptions& options) {
  manifold.validate();
  const int k = manifold.vertices_per_simplex();
  const int D = manifold.ambient_dimension();
  if (k != 3 && k != 4)
    fail<InputError>("subdivision needs tetrahedra (4 vertices) or triangles (3 vertices), got simplices of ", k,
                     " vertices");
  if (D < k - 1) fail<InputError>("simplices of ", k, " vertices need at least ", k - 1, " coordinates, got ", D);
  if (options.levels < 0) fail<InputError>("subdivision levels must be >= 0, got ", options.levels);
  const Index S = static_cast<Index>(manifold.S.rows());
  double growth = static_cast<double>(S);
  for (int l = 0; l < options.levels; ++l) growth *= (k == 4 ? 8 : 4);
  if (growth * k > static_cast<double>(kMaxIndex))
    fail<InputError>(options.levels, " levels of subdivision of ", S, " simplices would make ", growth,
                     " simplices, more than 32-bit indices hold");
  for (Index s = 0; s < S; ++s)
    for (int a = 0; a < k; ++a)
      for (int b = a + 1; b < k; ++b)
        if (manifold.S(s, a) == manifold.S(s, b))
          fail<InputError>("simplex ", s, " repeats vertex ", manifold.S(s, a), ": it is degenerate");
  for (double t : options.keyframe_times)
    if (!std::isfinite(t)) fail<InputError>("keyframe time ", t, " is not finite");
}

// The boundary facets (stride k - 1); adjacency throws on facets shared by
// three or more simplices.
std::vector<Index> boundary_facet_list(const SimplexMatrix& S) {
  const FacetAdjacency adjacency = facet_adjacency(S);
  const int k = static_cast<int>(S.cols());
  std::vector<Index> boundary;
  Index facet_buffer[4];
  for (Index s = 0; s < S.rows(); ++s)
    for (int i = 0; i < k; ++i)
      if (adjacency.neighbour(s, i) < 0) {
        facet(S.row(s).data(), k, i, facet_buffer);
        boundary.insert(boundary.end(), facet_buffer, facet_buffer + k - 1);
      }
  return boundary;
}

// Whether the n points c all have one time (the last coordinate), t.
bool flat_time(const PointMatrix& V, const Index* c, int n, double& t) {
  const Eigen::Index time = V.cols() - 1;
  t = V(c[0], time);
  for (int i = 1; i < n; ++i)
    if (V(c[i], time) != t) return false;
  return true;
}

// Keyframe times, sorted and each once: given, or every time of a facet
// lying on a hyperplane; the times of boundary facets on hyperplanes always count.
std::vector<double> keyframe_times(const Complex& manifold, const std::vector<Index>& boundary,
                                   const std::vector<double>& given) {
  const int k = manifold.vertices_per_simplex();
  const int f = k - 1;
  const Eigen::Index time = manifold.V.cols() - 1;
  std::vector<double> times = given;
  double t = 0;
  for (size_t b = 0; b < boundary.size(); b += f)
    if (flat_time(manifold.V, &boundary[b], f, t)) times.push_back(t);
  if (given.empty()) {
    std::array<double, 4> ts;
    for (Index s = 0; s < manifold.S.rows(); ++s) {
      for (int i = 0; i < k; ++i) ts[i] = manifold.V(manifold.S(s, i), time);
      std::sort(ts.begin(), ts.begin() + k);
      // Some k-1 of the k vertices share a time iff the first or the last k-1 sorted ones do.
      if (ts[0] == ts[k - 2]) times.push_back(ts[0]);
      else if (ts[1] == ts[k - 1]) times.push_back(ts[1]);
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

// Creases: (k-3)-faces of the boundary where the patch changes or the
// boundary is not a manifold; for tetrahedra also the corners where creases
// do not continue in exactly two segments.
void find_creases(Level& L) {
  const int f = L.k - 1;
  struct Record {
    std::array<Index, 2> key;
    int patch;
  };
  std::vector<Record> records;
  const size_t B = L.boundary_patch.size();
  for (size_t b = 0; b < B; ++b) {
    const Index* c = &L.boundary[b * f];
    if (f == 3) {
      for (const auto& e : kTriEdges)
        records.push_back({{std::min(c[e[0]], c[e[1]]), std::max(c[e[0]], c[e[1]])}, L.boundary_patch[b]});
    } else {
      for (int i = 0; i < 2; ++i) records.push_back({{c[i], -1}, L.boundary_patch[b]});
    }
  }
  std::sort(records.begin(), records.end(), [](const Record& a, const Record& b) {
    return a.key != b.key ? a.key < b.key : a.patch < b.patch;
  });
  for (size_t begin = 0; begin < records.size();) {
    size_t end = begin + 1;
    while (end < records.size() && records[end].key == records[begin].key) ++end;
    const bool crease = (end - begin != 2) || records[begin].patch != records[end - 1].patch;
    if (crease) {
      L.creases.push_back(records[begin].key[0]);
      if (f == 3) L.creases.push_back(records[begin].key[1]);
    }
    begin = end;
  }
  if (f != 3) return;
  std::vector<Index> ends = L.creases;
  std::sort(ends.begin(), ends.end());
  for (size_t begin = 0; begin < ends.size();) {
    size_t end = begin + 1;
    while (end < ends.size() && ends[end] == ends[begin]) ++end;
    if (end - begin != 2) L.corners.push_back(ends[begin]);
    begin = end;
  }
}

// The manifold as level 0: its points with their attributes, simplices,
// boundary patches, creases and keyframes.
Level first_level(const Complex& manifold, std::vector<Index> boundary, const std::vector<double>& times) {
  const int k = manifold.vertices_per_simplex();
  const int f = k - 1;
  const int D = manifold.ambient_dimension();
  Level L;
  L.k = k;
  L.boundary = std::move(boundary);
  double t = 0;
  for (size_t b = 0; b < L.boundary.size(); b += f)
    L.boundary_patch.push_back(flat_time(manifold.V, &L.boundary[b], f, t) ? time_index(times, t) : -1);
  find_creases(L);
  L.X = pack_columns(manifold.V, manifold.vertex_attributes);
  L.simplices.assign(manifold.S.data(), manifold.S.data() + manifold.S.size());
  L.simplex_root.resize(manifold.S.rows());
  std::iota(L.simplex_root.begin(), L.simplex_root.end(), 0);
  L.keyframe.resize(manifold.V.rows());
  for (Eigen::Index v = 0; v < manifold.V.rows(); ++v) L.keyframe[v] = time_index(times, manifold.V(v, D - 1));
  L.parents.resize(manifold.V.rows(), 2);
  for (Eigen::Index v = 0; v < manifold.V.rows(); ++v) L.parents.row(v) << static_cast<Index>(v), static_cast<Index>(v);
  return L;
}

// Which of an octahedron's three diagonals (opposite pairs) is shortest,
// ties broken by the smaller vertex id so that the choice is reproducible.
int shortest_diagonal(const Level& L, const std::array<Index, 6>& c, int D) {
  int best = 0;
  double best_length = 0;
  for (int p = 0; p < 3; ++p) {
    const double length = (L.X.row(c[2 * p]).head(D) - L.X.row(c[2 * p + 1]).head(D)).squaredNorm();
    const Index id = std::min(c[2 * p], c[2 * p + 1]);
    const Index best_id = std::min(c[2 * best], c[2 * best + 1]);
    const double tolerance = 1e-12 * std::max(length, best_length);
    if (p == 0 || length < best_length - tolerance || (std::abs(length - best_length) <= tolerance && id < best_id)) {
      best = p;
      best_length = length;
    }
  }
  return best;
}

// The last level's simplices, octahedra cut along their shortest diagonal,
// into out.manifold.S with their input simplex in out.simplex_parent.
void cut_octahedra(const Level& L, int D, ManifoldSubdivision& out) {
  const int k = L.k;
  const Tables& T = tables();
  const size_t outS = L.simplices.size() / k + 4 * L.octs.size();
  out.manifold.S.resize(static_cast<Eigen::Index>(outS), k);
  out.simplex_parent.resize(static_cast<Eigen::Index>(outS));
  std::copy(L.simplices.begin(), L.simplices.end(), out.manifold.S.data());
  std::copy(L.simplex_root.begin(), L.simplex_root.end(), out.simplex_parent.data());
  const Eigen::Index first = static_cast<Eigen::Index>(L.simplices.size() / k);
  // Octahedron o's four tetrahedra are rows first + 4o..: its own, whatever the thread count.
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (size_t o = 0; o < L.octs.size(); ++o) {
    const auto& c = L.octs[o];
    Eigen::Index row = first + 4 * static_cast<Eigen::Index>(o);
    for (const auto& child : T.oct_cut[shortest_diagonal(L, c, D)]) {
      for (int i = 0; i < 4; ++i) out.manifold.S(row, i) = c[child[i]];
      out.simplex_parent(row) = L.oct_root[o];
      ++row;
    }
  }
}

// How far a subdivision into `levels` levels is when level `level` starts:
// each level costs eight times the one before, and the levels span [0.05, 0.9].
double level_fraction(int level, int levels) {
  return loop_fraction(0.05, 0.9, (1ll << (3 * level)) - 1, (1ll << (3 * levels)) - 1);
}

}  // namespace

ManifoldSubdivision subdivide_manifold(const Complex& manifold, const ManifoldSubdivisionOptions& options,
                                       const Interrupter& interrupter) {
  interrupter.step("checks", 0);
  check_memory(manifold_subdivision_memory(manifold, options.levels));
  check_manifold_input(manifold, options);
  const int D = manifold.ambient_dimension();
  std::vector<Index> boundary = boundary_facet_list(manifold.S);
  const std::vector<double> times = keyframe_times(manifold, boundary, options.keyframe_times);
  Level L = first_level(manifold, std::move(boundary), times);
  for (int level = 0; level < options.levels; ++level) {
    interrupter.step("refining", level_fraction(level, options.levels));
    L = refine(L);
    if (options.scheme != ManifoldScheme::Schaefer) continue;
    interrupter.step("averaging", (level_fraction(level, options.levels) + level_fraction(level + 1, options.levels)) / 2);
    average(L, D, times, options.keep_keyframe_times);
  }

  interrupter.step("octahedra", 0.9);
  ManifoldSubdivision out;
  cut_octahedra(L, D, out);
  out.manifold.V = L.X.leftCols(D);
  out.manifold.vertex_attributes = unpack_columns(L.X, D, manifold.vertex_attributes);
  out.manifold.simplex_attributes = inherit_rows(manifold.simplex_attributes, out.simplex_parent);
  out.vertex_parents = std::move(L.parents);
  out.keyframe_times = Eigen::Map<const Eigen::VectorXd>(times.data(), static_cast<Eigen::Index>(times.size()));
  return out;
}

}  // namespace animanifold
