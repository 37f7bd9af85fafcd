// The push of the free vertices into time (§8.6.3; see morph_skeleton.hpp).
#include "animanifold/morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace animanifold {

namespace {

// What the push must keep positive: a simplex of the fill (D+1 corners), or
// a boundary facet of it (D corners) measured within its own hyperplane —
// its normal as the last row of the matrix — times the facet's sign then.
// Where the fill's boundary is flat across both planes (two tori with their
// bottoms at the same height make a facet of the 4D hull in z = -0.35), the
// simplices behind it are slivers of the perturbation whose sign says
// nothing; the facets themselves could then fold within the hyperplane, and
// the frames would overlap themselves there.
struct PushConstraint {
  std::array<Index, 5> corners{-1, -1, -1, -1, -1};
  int count = 0;
  Eigen::VectorXd normal;  // facets only
  double sign = 1.0;
};

// The determinant of a small square matrix: closed forms for 3x3 and 4x4
// (the push evaluates hundreds of thousands per round; the general LU of a
// dynamic-size matrix costs several times more).
double small_determinant(const Eigen::MatrixXd& m) {
  if (m.rows() == 4) return Eigen::Matrix4d(m).determinant();
  if (m.rows() == 3) return Eigen::Matrix3d(m).determinant();
  return m.determinant();
}

// (value, rate) of a constraint's determinant under moves of its corners
// along the last axis by `share(v)` per unit of the move parameter.
template <class Share>
std::pair<double, double> affine_volume(const PointMatrix& P, const PushConstraint& k, const Share& share,
                                        Eigen::MatrixXd& m) {
  const int D = static_cast<int>(P.cols());
  for (int c = 1; c < k.count; ++c) m.row(c - 1) = P.row(k.corners[c]) - P.row(k.corners[0]);
  if (k.count == D) m.row(D - 1) = k.normal.transpose();
  const double before = k.sign * small_determinant(m);
  for (int c = 1; c < k.count; ++c) m(c - 1, D - 1) = share(k.corners[c]) - share(k.corners[0]);
  if (k.count == D) m(D - 1, D - 1) = 0.0;
  return {before, k.sign * small_determinant(m)};
}

}  // namespace

PushReport push_free_vertices(PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& moved, double direction,
                              const Eigen::VectorXd& target, double safety, int sweeps) {
  const int D = static_cast<int>(P.cols());
  if (A.cols() != D + 1) fail<InputError>("pushing needs ", D, "-simplices in R^", D, ", got ", A.cols(), " corners");
  PushReport report;
  std::vector<PushConstraint> constraints;
  auto touches = [&](const Index* ids, int count) {
    for (int c = 0; c < count; ++c)
      if (moved[ids[c]]) return true;
    return false;
  };
  for (Index s = 0; s < A.rows(); ++s)
    if (touches(A.row(s).data(), D + 1)) {
      PushConstraint k;
      std::copy(A.row(s).data(), A.row(s).data() + D + 1, k.corners.begin());
      k.count = D + 1;
      constraints.push_back(k);
    }
  const SimplexMatrix boundary = boundary_facets(A);
  const double size = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  Eigen::MatrixXd basis(D - 1, D), m(D, D);
  for (Index f = 0; f < boundary.rows(); ++f) {
    if (!touches(boundary.row(f).data(), D)) continue;
    for (int c = 1; c < D; ++c) basis.row(c - 1) = P.row(boundary(f, c)) - P.row(boundary(f, 0));
    Eigen::FullPivLU<Eigen::MatrixXd> lu(basis);
    if (lu.dimensionOfKernel() != 1) continue;
    PushConstraint k;
    std::copy(boundary.row(f).data(), boundary.row(f).data() + D, k.corners.begin());
    k.count = D;
    k.normal = lu.kernel().col(0).normalized();
    const double measure = affine_volume(P, k, [](Index) { return 0.0; }, m).first;
    if (std::abs(measure) <= 1e-9 * std::pow(size, D - 1)) continue;  // flat already: nothing to keep
    k.sign = measure > 0 ? 1.0 : -1.0;
    constraints.push_back(k);
  }
  std::vector<std::vector<Index>> star(P.rows());
  for (size_t i = 0; i < constraints.size(); ++i)
    for (int c = 0; c < constraints[i].count; ++c)
      if (moved[constraints[i].corners[c]]) star[constraints[i].corners[c]].push_back(static_cast<Index>(i));
  std::vector<double> travelled(P.rows(), 0.0);
  // How far v may go before a constraint of its star goes flat, the others
  // where they are now: value(δ) = before + δ·rate (v's last coordinate sits
  // in the last column only, and the determinant is linear in that column).
  auto limit_of = [&](Index v, bool count_degenerate) {
    double limit = std::numeric_limits<double>::infinity();
    for (const Index i : star[v]) {
      const auto [before, rate] = affine_volume(P, constraints[i], [&](Index w) { return w == v ? direction : 0.0; }, m);
      if (!(before > 0)) {
        report.degenerate += count_degenerate;
        continue;
      }
      if (rate < 0) limit = std::min(limit, -before / rate);
    }
    return limit;
  };
  // First all free vertices together: each moves by its share of one
  // common parameter Δ (target(v)/largest·Δ). Every constraint is then
  // affine in Δ too (its moved corners' last coordinates are affine in Δ,
  // all in one column), so the largest safe Δ is exact. Together, free
  // vertices that share a sliver move as one and do not flatten it, which
  // a vertex moved alone would at once (a chord's point and the faces it
  // lines up with on symmetric inputs). Vertices of the constraints that
  // stop the common move are frozen where they are, and the others go on.
  const double largest = target.size() ? target.maxCoeff() : 0.0;
  std::vector<bool> active(P.rows(), false);
  for (Index v = 0; v < P.rows(); ++v) active[v] = moved[v] && target(v) > 0;
  double done = 0;
  for (int round = 0; round < 64 && largest > 0 && done < largest; ++round) {
    std::vector<double> limit(constraints.size(), std::numeric_limits<double>::infinity());
    double smallest = std::numeric_limits<double>::infinity();
    auto share = [&](Index v) { return active[v] ? direction * target(v) / largest : 0.0; };
    for (size_t i = 0; i < constraints.size(); ++i) {
      const PushConstraint& k = constraints[i];
      bool any = false;
      for (int c = 0; c < k.count; ++c) any = any || active[k.corners[c]];
      if (!any) continue;
      const auto [before, rate] = affine_volume(P, k, share, m);
      if (before > 0 && rate < 0) smallest = std::min(smallest, limit[i] = -before / rate);
    }
    const double remaining = largest - done;
    const double step = std::min(remaining, safety * smallest);
    for (Index v = 0; v < P.rows(); ++v)
      if (active[v]) {
        P(v, D - 1) += direction * target(v) / largest * step;
        travelled[v] += target(v) / largest * step;
      }
    done += step;
    if (step >= remaining) break;
    // Freeze the corners of the constraints that would stop the next steps soon.
    for (size_t i = 0; i < constraints.size(); ++i)
      if (limit[i] - step <= 2 * (smallest - step))
        for (int c = 0; c < constraints[i].count; ++c) active[constraints[i].corners[c]] = false;
  }
  // Then each frozen vertex alone, as far as its own constraints allow.
  const int levels = std::max(1, sweeps) * 4;
  for (int level = 1; level <= levels + 2; ++level) {
    for (Index v = 0; v < P.rows(); ++v) {
      const double height = moved[v] ? target(v) * std::min(level, levels) / levels : 0.0;
      if (!moved[v] || travelled[v] >= height) continue;
      const double step = std::min(height - travelled[v], safety * limit_of(v, level == 1));
      if (!(step > 0)) continue;
      P(v, D - 1) += direction * step;
      travelled[v] += step;
    }
  }
  double sum = 0;
  report.smallest = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < P.rows(); ++v) {
    if (!moved[v]) continue;
    ++report.vertices;
    report.held_back += travelled[v] < 0.1 * target(v);
    sum += travelled[v];
    report.smallest = std::min(report.smallest, travelled[v]);
    report.largest = std::max(report.largest, travelled[v]);
  }
  if (report.vertices == 0) report.smallest = 0;
  report.mean = report.vertices ? sum / report.vertices : 0.0;
  return report;
}

}  // namespace animanifold
