// The blend's distances measured through the inputs (morph_field_internal.hpp).
#include "animanifold/laplacian.hpp"
#include "morph_field_internal.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>

namespace animanifold::morph_field {

namespace {

// Per point, the length of the shortest path along the tetrahedralization's
// edges (`ring`) that keeps to points where `inside` is negative, from the
// points where `from` is not positive either (Dijkstra's); infinity where no
// such path reaches.
Eigen::VectorXd path_inside(const VertexAdjacency& ring, const PointMatrix& points, const Eigen::VectorXd& inside,
                            const Eigen::VectorXd& from) {
  const Index n = static_cast<Index>(points.rows());
  Eigen::VectorXd length = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (Index v = 0; v < n; ++v)
    if (inside(v) < 0 && from(v) <= 0) length(v) = 0, queue.push({0.0, v});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > length(v)) continue;
    for (Index k = ring.offsets[static_cast<size_t>(v)]; k < ring.offsets[static_cast<size_t>(v) + 1]; ++k) {
      const Index u = ring.neighbours[static_cast<size_t>(k)];
      if (inside(u) >= 0) continue;
      const double through = d + (points.row(u) - points.row(v)).norm();
      if (through < length(u)) length(u) = through, queue.push({through, u});
    }
  }
  return length;
}

}  // namespace

void distances_through_inputs(const SimplexMatrix& cells, const PointMatrix& points, double spacing,
                              Eigen::VectorXd& s, Eigen::VectorXd& t) {
  const VertexAdjacency ring = vertex_adjacency(cells, static_cast<Index>(points.rows()));
  const Eigen::VectorXd through_T = path_inside(ring, points, t, s);
  const Eigen::VectorXd through_S = path_inside(ring, points, s, t);
  const double slack = kThroughSlack * spacing;
  for (Index v = 0; v < s.size(); ++v) {
    if (t(v) < 0 && s(v) > 0 && std::isfinite(through_T(v))) s(v) = std::max(s(v), through_T(v) - slack);
    else if (s(v) < 0 && t(v) > 0 && std::isfinite(through_S(v))) t(v) = std::max(t(v), through_S(v) - slack);
  }
}

}  // namespace animanifold::morph_field
