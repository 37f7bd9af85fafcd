// Corner charts (corner_charts.hpp).
#include "animanifold/corner_charts.hpp"

#include "animanifold/errors.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace animanifold {

namespace {

// Each vertex's corners (as flat indices into the simplices), grouped by
// vertex in ascending order: a counting sort.
struct CornersByVertex {
  std::vector<Index> start, corner;
  CornersByVertex(const SimplexMatrix& simplices, Index vertices) : start(static_cast<size_t>(vertices) + 1, 0) {
    const Index* v = simplices.data();
    const Index corners = static_cast<Index>(simplices.size());
    const Index k = static_cast<Index>(simplices.cols());
    for (Index c = 0; c < corners; ++c) {
      if (v[c] < 0 || v[c] >= vertices)
        fail<InputError>("simplex ", c / k, " has vertex ", v[c], ", out of range for ", vertices, " vertices");
      ++start[static_cast<size_t>(v[c]) + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    corner.resize(static_cast<size_t>(corners));
    std::vector<Index> at(start.begin(), start.end() - 1);
    for (Index c = 0; c < corners; ++c) corner[static_cast<size_t>(at[v[c]]++)] = c;
  }
};

// numpy's order for floats: NaN after every number, NaNs equal.
bool before(double a, double b) { return std::isnan(b) ? !std::isnan(a) : a < b; }

// Union-find whose root is always the smallest item of its group.
struct SmallestRoot {
  std::vector<Index> parent;
  explicit SmallestRoot(Index n) : parent(static_cast<size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(Index a, Index b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

VertexFacePairs vertex_face_pairs(const SimplexMatrix& simplices, const IndexVector& face, Index vertices) {
  if (face.size() != simplices.rows())
    fail<InputError>("vertex_face_pairs takes one face per simplex: ", face.size(), " for ", simplices.rows());
  if (vertices < 0) fail<InputError>("vertex_face_pairs: the vertex count is negative (", vertices, ")");
  const Index k = static_cast<Index>(simplices.cols());
  const CornersByVertex by_vertex(simplices, vertices);
  VertexFacePairs out;
  out.corner_pair.resize(simplices.rows(), k);
  std::vector<Index> pair_vertex, pair_face;
  std::vector<std::pair<Index, Index>> mine;  // (face, corner) of one vertex's corners
  for (Index v = 0; v < vertices; ++v) {
    mine.clear();
    for (Index i = by_vertex.start[v]; i < by_vertex.start[v + 1]; ++i) {
      const Index c = by_vertex.corner[static_cast<size_t>(i)];
      mine.emplace_back(face(c / k), c);
    }
    std::sort(mine.begin(), mine.end());
    for (size_t i = 0; i < mine.size(); ++i) {
      if (i == 0 || mine[i].first != mine[i - 1].first) {
        pair_vertex.push_back(v);
        pair_face.push_back(mine[i].first);
      }
      out.corner_pair.data()[mine[i].second] = static_cast<Index>(pair_vertex.size()) - 1;
    }
  }
  out.vertex = Eigen::Map<const IndexVector>(pair_vertex.data(), static_cast<Index>(pair_vertex.size()));
  out.face = Eigen::Map<const IndexVector>(pair_face.data(), static_cast<Index>(pair_face.size()));
  return out;
}

IndexVector chart_labels(const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>& owner,
                         const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& uv,
                         const Eigen::VectorXd& tolerance) {
  const Index n = static_cast<Index>(owner.size());
  if (uv.rows() != n || tolerance.size() != n)
    fail<InputError>("chart_labels takes one UV and one tolerance per item: ", uv.rows(), " UVs and ",
                     tolerance.size(), " tolerances for ", n, " items");
  SmallestRoot groups(n);
  std::vector<Index> order(static_cast<size_t>(n));
  for (const int first : {0, 1}) {
    const int second = 1 - first;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
      if (owner(a) != owner(b)) return owner(a) < owner(b);
      if (before(uv(a, first), uv(b, first))) return true;
      if (before(uv(b, first), uv(a, first))) return false;
      return before(uv(a, second), uv(b, second));
    });
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = order[i], b = order[i + 1];
      if (owner(a) == owner(b) && std::abs(uv(a, 0) - uv(b, 0)) <= tolerance(a) &&
          std::abs(uv(a, 1) - uv(b, 1)) <= tolerance(a))
        groups.join(a, b);
    }
  }
  IndexVector label(n);
  Index groups_so_far = 0;
  for (Index i = 0; i < n; ++i) {
    const Index root = groups.find(i);
    label(i) = root == i ? groups_so_far++ : label(root);
  }
  return label;
}

}  // namespace animanifold
