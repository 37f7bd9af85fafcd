// The push of the free vertices into time (§8.6.3; see morph_skeleton.hpp).
#include "animanifold/morph_skeleton.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>
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
  // The determinant (a facet's times the sign that makes it positive at the
  // start) is
  // `constant` + Σ weight[c]·(t[c] - t[0]) over the corners' last
  // coordinates t (the only ones the push moves): the cofactors of the last
  // column, which depend on the other coordinates only, are computed once,
  // and every evaluation after that is a dot product.
  std::array<double, 5> weight{0, 0, 0, 0, 0};
  double constant = 0.0;
};

// Square matrices of up to 4x4 on the stack (morphs in 2D and 3D: D = 3, 4).
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;

// The matrix of a constraint: rows from corner 0 to the others, and for a
// facet its hyperplane's normal (kept as it is at the start) as the last row.
SmallMatrix constraint_matrix(const PointMatrix& P, const std::array<Index, 5>& corners, int count,
                              const Eigen::VectorXd* normal) {
  const int D = static_cast<int>(P.cols());
  SmallMatrix m(D, D);
  for (int c = 1; c < count; ++c) m.row(c - 1) = P.row(corners[c]) - P.row(corners[0]);
  if (normal) m.row(D - 1) = normal->transpose();
  return m;
}

// The determinant of a small square matrix: closed forms for 3x3 and 4x4.
double small_determinant(const SmallMatrix& m) {
  if (m.rows() == 4) return Eigen::Matrix4d(m).determinant();
  if (m.rows() == 3) return Eigen::Matrix3d(m).determinant();
  return m.determinant();
}

// A constraint over `corners` (`count` of them; a facet when `normal` is
// given) with its weights; `measure` gets its determinant now. A facet is
// turned so that it is positive now (its normal's direction is arbitrary); a
// simplex keeps the orientation the fill gave it.
PushConstraint linear_constraint(const PointMatrix& P, const std::array<Index, 5>& corners, int count,
                                 const Eigen::VectorXd* normal, double& measure) {
  const int D = static_cast<int>(P.cols());
  const SmallMatrix m = constraint_matrix(P, corners, count, normal);
  measure = small_determinant(m);
  PushConstraint k;
  k.corners = corners;
  k.count = count;
  std::array<double, 5> cofactor{};
  for (int r = 0; r < D; ++r) {
    SmallMatrix e = m;
    e.col(D - 1).setZero();
    e(r, D - 1) = 1.0;
    cofactor[r] = small_determinant(e);
  }
  const double sign = normal && measure < 0 ? -1.0 : 1.0;
  for (int c = 1; c < count; ++c) k.weight[c] = sign * cofactor[c - 1];
  if (normal) k.constant = sign * (*normal)(D - 1) * cofactor[D - 1];
  return k;
}

// (value, rate) of a constraint under moves of its corners along the last
// axis by `share(v)` per unit of the move parameter.
template <class Share>
std::pair<double, double> affine_volume(const PointMatrix& P, const PushConstraint& k, const Share& share) {
  const Index last = P.cols() - 1;
  const Index first = k.corners[0];
  const double t0 = P(first, last), s0 = share(first);
  double value = k.constant, rate = 0.0;
  for (int c = 1; c < k.count; ++c) {
    value += k.weight[c] * (P(k.corners[c], last) - t0);
    rate += k.weight[c] * (share(k.corners[c]) - s0);
  }
  return {value, rate};
}

// Rounds of bringing enclosed peaks down (push_free_vertices).
constexpr int LEVELLING_ROUNDS = 4;
// What each constraint keeps while they come down: a share of its value
// when the levelling began (push_free_vertices).
constexpr double LEVELLING_FLOOR = 0.01;

// How low each free vertex of one plane must come for the frames to hold no
// bubble, in units of the last axis from the plane: the pushed free
// vertices make a height field over the plane's cells outside the input
// (the frame at height h crosses them where the field is h), and the space
// above the field at h is a bubble where it does not reach the convex
// hull's boundary, whose vertices are the free corners of the facets that
// leave the plane (sinks). A peak enclosed by vertices a sliver held back
// is one. Its level is the best over paths to a sink of the lowest height
// on the path (a widest-path search from the sinks, highest first): every
// vertex above a height then reaches a sink above it. Each level is at most
// the vertex's own height; vertices no path reaches keep theirs.
std::vector<double> enclosed_peak_levels(const SimplexMatrix& boundary, const std::vector<bool>& moved,
                                         const Eigen::VectorXd& start, const std::vector<double>& height) {
  const Index n = static_cast<Index>(moved.size());
  std::vector<double> level(height);
  double plane = 0;
  for (Index v = 0; v < n; ++v)
    if (moved[v]) {
      plane = start(v);
      break;
    }
  const double span = start.size() ? start.maxCoeff() - start.minCoeff() : 0.0;
  auto in_plane = [&](Index v) { return std::abs(start(v) - plane) <= 1e-12 * std::max(span, 1.0); };
  std::vector<std::vector<Index>> neighbours(n);
  std::vector<bool> sink(n, false);
  for (Index f = 0; f < boundary.rows(); ++f) {
    const Index* corner = boundary.row(f).data();
    const int count = static_cast<int>(boundary.cols());
    bool flat = true;
    for (int c = 0; c < count; ++c) flat = flat && in_plane(corner[c]);
    for (int a = 0; a < count; ++a) {
      if (!moved[corner[a]]) continue;
      if (!flat) sink[corner[a]] = true;
      else
        for (int b = 0; b < count; ++b)
          if (b != a && moved[corner[b]]) neighbours[corner[a]].push_back(corner[b]);
    }
  }
  std::vector<bool> reached(n, false);
  std::priority_queue<std::pair<double, Index>> widest;  // (level, vertex), highest first
  for (Index v = 0; v < n; ++v)
    if (sink[v]) reached[v] = true, widest.emplace(height[v], v);
  while (!widest.empty()) {
    const auto [at, v] = widest.top();
    widest.pop();
    if (at < level[v]) continue;  // a better path came first
    for (const Index u : neighbours[v]) {
      const double through = std::min(height[u], at);
      if (!reached[u] || through > level[u]) reached[u] = true, level[u] = through, widest.emplace(through, u);
    }
  }
  return level;
}

}  // namespace

PushReport push_free_vertices(PointMatrix& P, const SimplexMatrix& A, const std::vector<bool>& moved, double direction,
                              const Eigen::VectorXd& target, double safety, int sweeps,
                              const SimplexMatrix* given_boundary, bool level_enclosed_peaks) {
  const int D = static_cast<int>(P.cols());
  if (A.cols() != D + 1) fail<InputError>("pushing needs ", D, "-simplices in R^", D, ", got ", A.cols(), " corners");
  PushReport report;
  if (std::find(moved.begin(), moved.end(), true) == moved.end()) return report;  // nothing to push
  std::vector<PushConstraint> constraints;
  auto touches = [&](const Index* ids, int count) {
    for (int c = 0; c < count; ++c)
      if (moved[ids[c]]) return true;
    return false;
  };
  std::array<Index, 5> corners{-1, -1, -1, -1, -1};
  double measure = 0.0;
  for (Index s = 0; s < A.rows(); ++s)
    if (touches(A.row(s).data(), D + 1)) {
      std::copy(A.row(s).data(), A.row(s).data() + D + 1, corners.begin());
      constraints.push_back(linear_constraint(P, corners, D + 1, nullptr, measure));
    }
  const SimplexMatrix own_boundary = given_boundary ? SimplexMatrix() : boundary_facets(A);
  const SimplexMatrix& boundary = given_boundary ? *given_boundary : own_boundary;
  const double size = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  Eigen::MatrixXd basis(D - 1, D);
  for (Index f = 0; f < boundary.rows(); ++f) {
    if (!touches(boundary.row(f).data(), D)) continue;
    for (int c = 1; c < D; ++c) basis.row(c - 1) = P.row(boundary(f, c)) - P.row(boundary(f, 0));
    Eigen::FullPivLU<Eigen::MatrixXd> lu(basis);
    if (lu.dimensionOfKernel() != 1) continue;
    const Eigen::VectorXd normal = lu.kernel().col(0).normalized();
    std::copy(boundary.row(f).data(), boundary.row(f).data() + D, corners.begin());
    PushConstraint k = linear_constraint(P, corners, D, &normal, measure);
    if (std::abs(measure) <= 1e-9 * std::pow(size, D - 1)) continue;  // flat already: nothing to keep
    constraints.push_back(k);
  }
  std::vector<std::vector<Index>> star(P.rows());
  for (size_t i = 0; i < constraints.size(); ++i)
    for (int c = 0; c < constraints[i].count; ++c)
      if (moved[constraints[i].corners[c]]) star[constraints[i].corners[c]].push_back(static_cast<Index>(i));
  std::vector<double> travelled(P.rows(), 0.0);
  const Eigen::VectorXd start = P.col(D - 1);
  // How far v may go before a constraint of its star goes flat, the others
  // where they are now: value(δ) = before + δ·rate (v's last coordinate sits
  // in the last column only, and the determinant is linear in that column).
  auto limit_of = [&](Index v, bool count_degenerate) {
    double limit = std::numeric_limits<double>::infinity();
    for (const Index i : star[v]) {
      const auto [before, rate] = affine_volume(P, constraints[i], [&](Index w) { return w == v ? direction : 0.0; });
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
  // Each constraint's value is affine in Δ with a rate that changes only
  // when one of its corners freezes, so the Δ at which it would go flat is
  // known in advance and kept in a queue (earliest first), renewed for the
  // stars of the vertices that freeze: no round looks at every constraint.
  double done = 0;
  std::vector<int> version(constraints.size(), 0);
  using Event = std::tuple<double, size_t, int>;  // (Δ at which it goes flat, constraint, version)
  std::priority_queue<Event, std::vector<Event>, std::greater<Event>> flat_at;
  auto schedule = [&](size_t i) {
    ++version[i];
    const auto [before, rate] =
        affine_volume(P, constraints[i], [&](Index v) { return active[v] ? direction * target(v) / largest : 0.0; });
    if (before > 0 && rate < 0) flat_at.emplace(done - before / rate, i, version[i]);
  };
  auto drop_stale = [&] {
    while (!flat_at.empty() && std::get<2>(flat_at.top()) != version[std::get<1>(flat_at.top())]) flat_at.pop();
  };
  if (largest > 0)
    for (size_t i = 0; i < constraints.size(); ++i) {
      const PushConstraint& k = constraints[i];
      for (int c = 0; c < k.count; ++c)
        if (active[k.corners[c]]) {
          schedule(i);
          break;
        }
    }
  std::vector<Index> frozen;
  for (int round = 0; round < 64 && largest > 0 && done < largest; ++round) {
    drop_stale();
    const double smallest = flat_at.empty() ? std::numeric_limits<double>::infinity() : std::get<0>(flat_at.top()) - done;
    const double remaining = largest - done;
    const double step = std::min(remaining, safety * smallest);
    for (Index v = 0; v < P.rows(); ++v)
      if (active[v]) {
        P(v, D - 1) += direction * target(v) / largest * step;
        travelled[v] += target(v) / largest * step;
      }
    done += step;
    if (step >= remaining) break;
    // Freeze the corners of the constraints that would stop the next steps
    // soon (within twice the nearest's distance), then renew the stars of
    // the vertices frozen: their constraints' rates changed.
    const double soon = done + 2 * (smallest - step);
    frozen.clear();
    for (drop_stale(); !flat_at.empty() && std::get<0>(flat_at.top()) <= soon; drop_stale()) {
      const size_t i = std::get<1>(flat_at.top());
      flat_at.pop();
      ++version[i];  // its corners freeze: renewed below with the others
      for (int c = 0; c < constraints[i].count; ++c) {
        const Index v = constraints[i].corners[c];
        if (active[v]) active[v] = false, frozen.push_back(v);
      }
    }
    for (const Index v : frozen)
      for (const Index i : star[v]) schedule(static_cast<size_t>(i));
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
  for (Index v = 0; v < P.rows(); ++v) report.held_back += moved[v] && travelled[v] < 0.1 * target(v);
  // Last, the peaks that held-back vertices enclose come down towards them
  // (see enclosed_peak_levels), each vertex alone and as far as its
  // constraints allow, in the same steps. Steps of a share of the room left
  // would take a constraint that stops several vertices, round after round,
  // to a few ulps above zero, and the exact coordinates would invert it:
  // instead every constraint keeps LEVELLING_FLOOR of what it had when the
  // levelling began. A vertex that cannot come all the way is a lower wall
  // for those behind it: the levels are found again from where everything
  // is then. (A constraint that is not positive when it begins, which the
  // push ignored, stops any move that would lower it further.)
  std::vector<double> floor_of(level_enclosed_peaks ? constraints.size() : 0, 0.0);
  for (size_t i = 0; i < floor_of.size(); ++i)
    floor_of[i] = LEVELLING_FLOOR * affine_volume(P, constraints[i], [](Index) { return 0.0; }).first;
  auto room_down = [&](Index v) {  // how far v may come down, the others where they are
    double room = std::numeric_limits<double>::infinity();
    for (const Index i : star[v]) {
      const auto [value, rate] = affine_volume(P, constraints[i], [&](Index w) { return w == v ? -direction : 0.0; });
      if (rate < 0) room = std::min(room, std::max(0.0, (value - floor_of[i]) / -rate));
    }
    return room;
  };
  // Vertices whose simplices stop each other alone (a sliver with two or
  // three of them) come down together first: each by the same share of the
  // way to its level, the largest share that keeps every floor (exact: the
  // constraints are affine in the share), then without the corners of the
  // constraints that stopped it, and so on.
  auto come_down_together = [&](const std::vector<double>& level_of) {
    std::vector<bool> going(P.rows(), false);
    for (Index v = 0; v < P.rows(); ++v) going[v] = moved[v] && travelled[v] > level_of[v];
    auto share = [&](Index w) { return going[w] ? -direction * (travelled[w] - level_of[w]) : 0.0; };
    bool lowered = false;
    for (int round = 0; round < 4 * LEVELLING_ROUNDS; ++round) {
      std::vector<std::pair<double, size_t>> stops;  // (share at which it reaches its floor, constraint)
      double best = 1.0;
      for (size_t i = 0; i < floor_of.size(); ++i) {
        bool touched = false;
        for (int c = 0; c < constraints[i].count && !touched; ++c) touched = going[constraints[i].corners[c]];
        if (!touched) continue;
        const auto [value, rate] = affine_volume(P, constraints[i], share);
        if (rate >= 0) continue;
        const double at = std::max(0.0, (value - floor_of[i]) / -rate);
        if (at < 1.0) stops.emplace_back(at, i);
        best = std::min(best, at);
      }
      if (best > 0) {
        for (Index v = 0; v < P.rows(); ++v)
          if (going[v]) {
            const double step = best * (travelled[v] - level_of[v]);
            P(v, D - 1) -= direction * step;
            travelled[v] -= step;
          }
        lowered = true;
      }
      if (stops.empty()) break;
      for (const auto& [at, i] : stops)  // those that stop it now or soon after
        if (at <= 2 * best)
          for (int c = 0; c < constraints[i].count; ++c) going[constraints[i].corners[c]] = false;
      if (std::find(going.begin(), going.end(), true) == going.end()) break;
    }
    return lowered;
  };
  const std::vector<double> pushed = travelled;
  for (int round = 0; level_enclosed_peaks && round < LEVELLING_ROUNDS; ++round) {
    const std::vector<double> level_of = enclosed_peak_levels(boundary, moved, start, travelled);
    bool lowered = come_down_together(level_of);
    for (int level = 1; level <= levels + 2; ++level) {
      for (Index v = 0; v < P.rows(); ++v) {
        if (!moved[v] || travelled[v] <= level_of[v]) continue;
        const double wanted = travelled[v] - (travelled[v] - level_of[v]) / std::max(1, levels + 1 - level);
        const double step = std::min(travelled[v] - wanted, room_down(v));
        if (!(step > 0)) continue;
        P(v, D - 1) -= direction * step;
        travelled[v] -= step;
        lowered = true;
      }
    }
    if (!lowered) break;
  }
  for (Index v = 0; v < P.rows(); ++v) report.levelled += moved[v] && travelled[v] < pushed[v];
  double sum = 0;
  report.smallest = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < P.rows(); ++v) {
    if (!moved[v]) continue;
    ++report.vertices;
    sum += travelled[v];
    report.smallest = std::min(report.smallest, travelled[v]);
    report.largest = std::max(report.largest, travelled[v]);
  }
  if (report.vertices == 0) report.smallest = 0;
  report.mean = report.vertices ? sum / report.vertices : 0.0;
  return report;
}

}  // namespace animanifold
