// The slabs of the field method's space-time triangulation (morph_field_internal.hpp).
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/exact_orientation.hpp"
#include "morph_field_internal.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace animanifold::morph_field {

namespace {

// Orientation of staircase simplex r of the prism over a positive tet whose
// vertices are in ascending order, in the prism's reference coordinates.
const std::array<int, 4>& staircase_signs() {
  static const std::array<int, 4> signs = [] {
    std::array<int, 4> out{};
    const Eigen::Matrix<double, 4, 3> corner = (Eigen::Matrix<double, 4, 3>() << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
                                                    .finished();
    for (int r = 0; r < 4; ++r) {
      Eigen::Matrix<double, 5, 4> p;
      for (int c = 0, row = 0; c < 4; ++c) {
        if (c <= 3 - r) p.row(row++) << corner.row(c), 0.0;
        if (c >= 3 - r) p.row(row++) << corner.row(c), 1.0;
      }
      Eigen::Matrix4d edges;
      for (int e = 0; e < 4; ++e) edges.row(e) = p.row(e + 1) - p.row(0);
      out[r] = edges.determinant() > 0 ? 1 : -1;
    }
    return out;
  }();
  return signs;
}

}  // namespace

void prism_simplices(const Index* c, Index bottom, Index top, Simplex4* out, const double* rank) {
  std::array<Index, 4> v{c[0], c[1], c[2], c[3]};
  auto before = [rank](Index a, Index b) { return rank && rank[a] != rank[b] ? rank[a] < rank[b] : a < b; };
  bool odd = false;
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && before(v[j], v[j - 1]); --j) std::swap(v[j - 1], v[j]), odd = !odd;
  for (int r = 0; r < 4; ++r) {
    Simplex4& s = out[r];
    int n = 0;
    for (int k = 0; k < 4; ++k) {
      if (k <= 3 - r) s[n++] = bottom + v[k];
      if (k >= 3 - r) s[n++] = top + v[k];
    }
    if ((staircase_signs()[r] < 0) != odd) std::swap(s[0], s[1]);
  }
}

std::vector<double> staircase_rank(const SimplexMatrix& cells, const Eigen::VectorXd& bottom,
                                   const Eigen::VectorXd& top) {
  const Index n = static_cast<Index>(bottom.size());
  std::vector<double> rank(n);
  for (Index v = 0; v < n; ++v) rank[v] = bottom(v) - top(v);
  const auto positive = [&](Index v) { return bottom(v) >= 0 && top(v) >= 0; };
  // Per point positive on both layers, its neighbours that join and that
  // leave, counted once per cell they share.
  std::vector<Index> joining(n, 0), leaving(n, 0);
  for (Index c = 0; c < cells.rows(); ++c)
    for (int a = 0; a < 4; ++a) {
      const Index q = cells(c, a);
      if (!positive(q)) continue;
      for (int b = 0; b < 4; ++b) {
        const Index v = cells(c, b);
        joining[q] += bottom(v) >= 0 && top(v) < 0;
        leaving[q] += bottom(v) < 0 && top(v) >= 0;
      }
    }
  constexpr double kLast = std::numeric_limits<double>::max();
  for (Index v = 0; v < n; ++v)
    if (positive(v) && joining[v] + leaving[v] > 0) rank[v] = joining[v] >= leaving[v] ? kLast : -kLast;
  return rank;
}

bool flat_to_rounding(const PointMatrix& X, const Simplex4& s, double time_scale) {
  constexpr double kFlatSimplex = 1e-12;
  Eigen::Matrix4d edges;
  double longest = 0;
  for (int e = 0; e < 4; ++e) {
    Eigen::RowVector4d d = X.row(s[e + 1]) - X.row(s[0]);
    d(3) *= time_scale;
    edges.row(e) = d;
    longest = std::max(longest, d.squaredNorm());
  }
  return std::abs(edges.determinant()) <= kFlatSimplex * longest * longest;
}

// ---------------------------------------------------------------- the fill


Fill fill_slab(const PointMatrix& PS, const PointMatrix& PT, double thickness) {
  const Index nS = static_cast<Index>(PS.rows()), nT = static_cast<Index>(PT.rows());
  PointMatrix P(nS + nT, 4);
  P << PS, Eigen::VectorXd::Zero(nS), PT, Eigen::VectorXd::Constant(nT, thickness);
  Fill fill;
  fill.simplices = delaunay_exact(P).simplices;
  std::vector<Index> source, target;
  for (Index s = 0; s < fill.simplices.rows(); ++s) {
    int below = 0;
    for (int c = 0; c < 5; ++c) below += fill.simplices(s, c) < nS;
    if (below != 4 && below != 1) continue;
    std::vector<Index>& cells = below == 4 ? source : target;
    for (int c = 0; c < 5; ++c) {
      const Index v = fill.simplices(s, c);
      if ((v < nS) == (below == 4)) cells.push_back(below == 4 ? v : v - nS);
    }
  }
  auto oriented = [](std::vector<Index>& ids, const PointMatrix& points) {
    SimplexMatrix cells = Eigen::Map<SimplexMatrix>(ids.data(), static_cast<Index>(ids.size() / 4), 4);
    for (Index c = 0; c < cells.rows(); ++c)
      if (exact_orientation(points, cells.row(c).data()) < 0) std::swap(cells(c, 0), cells(c, 1));
    return cells;
  };
  fill.source_cells = oriented(source, PS);
  fill.target_cells = oriented(target, PT);
  return fill;
}

}  // namespace animanifold::morph_field
