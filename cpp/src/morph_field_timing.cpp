// The blend's schedule in time (morph_field_internal.hpp): even motion.
#include "animanifold/errors.hpp"
#include "animanifold/surface_distance.hpp"
#include "animanifold/threads.hpp"
#include "morph_field_internal.hpp"
#include "zero_set.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace animanifold::morph_field {

namespace {

// Share of the schedule that follows the measured motion; the rest is
// linear in time, so that the weight never stalls where nothing moves.
constexpr double kFollowMotion = 0.85;
// Points each two-sided distance is measured on, at most per surface.
constexpr Index kDistanceSamples = 3000;
// An interval between two samples whose motion exceeds this multiple of the
// mean step is bisected (a hole closing, a limb appearing: fast events the
// even samples straddle), for at most kBisectionRounds rounds.
constexpr double kFastStep = 1.5;
constexpr int kBisectionRounds = 3;

struct Surface {
  PointMatrix V;
  SimplexMatrix F;
};

// The zero set of `value` (at `points`) over the positive tets `cells`.
Surface level_set(const SimplexMatrix& cells, const PointMatrix& points, const Eigen::VectorXd& value) {
  ZeroSetBuilder zero(4, static_cast<size_t>(points.rows()));
  for (Index c = 0; c < cells.rows(); ++c) {
    const Index* t = cells.row(c).data();
    const double v[4] = {value(t[0]), value(t[1]), value(t[2]), value(t[3])};
    zero.add(t, v, c);
  }
  Surface s;
  s.V.resize(static_cast<Index>(zero.cuts().size()), 3);
  for (size_t c = 0; c < zero.cuts().size(); ++c) {
    const ZeroCut& p = zero.cuts()[c];
    s.V.row(static_cast<Index>(c)) = (1 - p.s) * points.row(p.a) + p.s * points.row(p.b);
  }
  s.F = Eigen::Map<const SimplexMatrix>(zero.pieces().data(), static_cast<Index>(zero.piece_count()), 3);
  return s;
}

// Vertices and face centres of `s`, every k-th so that at most kDistanceSamples remain.
PointMatrix samples(const Surface& s) {
  const Index n = s.V.rows() + s.F.rows();
  const Index stride = std::max<Index>(1, n / kDistanceSamples);
  std::vector<double> xyz;
  for (Index i = 0; i < n; i += stride) {
    Eigen::RowVector3d p = i < s.V.rows() ? Eigen::RowVector3d(s.V.row(i)) : Eigen::RowVector3d::Zero();
    if (i >= s.V.rows()) {
      const Index f = i - s.V.rows();
      p = (s.V.row(s.F(f, 0)) + s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))) / 3.0;
    }
    xyz.insert(xyz.end(), {p(0), p(1), p(2)});
  }
  return Eigen::Map<const PointMatrix>(xyz.data(), static_cast<Index>(xyz.size() / 3), 3);
}

// A surface with its search tree, built once for the steps on both sides
// of it, and the points its distance to a neighbour is measured on.
struct Sampled {
  Surface surface;
  std::unique_ptr<TriangleDistance> distance;
  PointMatrix samples;
  explicit operator bool() const { return distance != nullptr; }
};

Sampled sampled(Surface s) {
  Sampled out;
  out.samples = samples(s);
  out.distance = std::make_unique<TriangleDistance>(s.V, s.F);
  out.surface = std::move(s);
  return out;
}

double two_sided(const Sampled& a, const Sampled& b) {
  if (a.surface.F.rows() == 0 || b.surface.F.rows() == 0) return 0.0;  // a frame with nothing in it: no measure
  return std::max(b.distance->farthest(a.samples), a.distance->farthest(b.samples));
}

}  // namespace

double BlendSchedule::operator()(double at) const {
  if (at <= u.front()) return w.front();
  if (at >= u.back()) return w.back();
  const size_t i = static_cast<size_t>(std::upper_bound(u.begin(), u.end(), at) - u.begin()) - 1;
  const double s = (at - u[i]) / (u[i + 1] - u[i]);
  return w[i] + s * (w[i + 1] - w[i]);
}

BlendSchedule motion_schedule(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                              const SimplexMatrix& FT, const SimplexMatrix& source_cells,
                              const SimplexMatrix& target_cells, const PointMatrix& PS, const PointMatrix& PT,
                              const Eigen::VectorXd& sS, const Eigen::VectorXd& tS, const Eigen::VectorXd& sT,
                              const Eigen::VectorXd& tT, int samples, double widening) {
  if (samples < 2) fail<InputError>("the motion schedule needs at least 2 samples");
  auto surface_at = [&](double w) -> Surface {
    if (w <= 0) return {VS, FS};
    if (w >= 1) return {VT, FT};
    const bool source_half = w <= 0.5;
    const Eigen::VectorXd &s = source_half ? sS : sT, &t = source_half ? tS : tT;
    Eigen::VectorXd value(s.size());
    for (Index v = 0; v < value.size(); ++v) {
      value(v) = blend(s(v), t(v), w, widening);
      if (value(v) == 0.0) value(v) = 1e-300;  // zero counts as outside (zero_set.hpp)
    }
    return level_set(source_half ? source_cells : target_cells, source_half ? PS : PT, value);
  };
  // Weights in increasing order, each with its surface and the motion from
  // the previous one (step[0] unused).
  std::vector<double> w;
  for (int i = 0; i <= samples; ++i) w.push_back(static_cast<double>(i) / samples);
  std::vector<Sampled> surfaces(w.size());
  std::vector<double> step(w.size(), -1.0);
  auto measure = [&] {
    // Independent samples and intervals: each writes its own slot, so the
    // result does not depend on the threads.
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (long i = 0; i < static_cast<long>(w.size()); ++i)
      if (!surfaces[i]) surfaces[i] = sampled(surface_at(w[i]));
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (long i = 1; i < static_cast<long>(w.size()); ++i)
      if (step[i] < 0) step[i] = two_sided(surfaces[i - 1], surfaces[i]);
  };
  measure();
  for (int round = 0; round < kBisectionRounds; ++round) {
    double total = 0;
    for (size_t i = 1; i < w.size(); ++i) total += step[i];
    const double mean = total / static_cast<double>(w.size() - 1);
    std::vector<double> w2{w[0]};
    std::vector<Sampled> surfaces2;
    surfaces2.push_back(std::move(surfaces[0]));
    std::vector<double> step2{-1.0};
    bool split = false;
    for (size_t i = 1; i < w.size(); ++i) {
      const bool fast = mean > 0 && step[i] > kFastStep * mean;
      if (fast) {
        w2.push_back(0.5 * (w[i - 1] + w[i]));
        surfaces2.emplace_back();
        step2.push_back(-1.0);
        split = true;
      }
      w2.push_back(w[i]);
      surfaces2.push_back(std::move(surfaces[i]));
      step2.push_back(fast ? -1.0 : step[i]);
    }
    if (!split) break;
    w = std::move(w2), surfaces = std::move(surfaces2), step = std::move(step2);
    measure();
  }
  std::vector<double> travelled{0.0};
  for (size_t i = 1; i < w.size(); ++i) travelled.push_back(travelled.back() + step[i]);
  BlendSchedule schedule;
  const double total = travelled.back();
  for (size_t i = 0; i < w.size(); ++i) {
    const double moved = total > 0 ? travelled[i] / total : w[i];
    schedule.w.push_back(w[i]);
    schedule.u.push_back(kFollowMotion * moved + (1 - kFollowMotion) * w[i]);
  }
  return schedule;
}

}  // namespace animanifold::morph_field
