// The blend's schedule in time (morph_field_internal.hpp): even motion.
#include "animanifold/errors.hpp"
#include "animanifold/surface_distance.hpp"
#include "morph_field_internal.hpp"
#include "zero_set.hpp"

#include <algorithm>
#include <cmath>

namespace animanifold::morph_field {

namespace {

// Share of the schedule that follows the measured motion; the rest is
// linear in time, so that the weight never stalls where nothing moves.
constexpr double kFollowMotion = 0.85;
// Points each two-sided distance is measured on, at most per surface.
constexpr Index kDistanceSamples = 3000;

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

double two_sided(const Surface& a, const Surface& b) {
  if (a.F.rows() == 0 || b.F.rows() == 0) return 0.0;  // a frame with nothing in it: no measure
  return std::max(max_distance_to_surface(samples(a), b.V, b.F), max_distance_to_surface(samples(b), a.V, a.F));
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
                              const Eigen::VectorXd& tT, int samples) {
  if (samples < 2) fail<InputError>("the motion schedule needs at least 2 samples");
  std::vector<Surface> surfaces;
  surfaces.push_back({VS, FS});
  for (int i = 1; i < samples; ++i) {
    const double w = static_cast<double>(i) / samples;
    const bool source_half = 2 * i <= samples;
    const Eigen::VectorXd& s = source_half ? sS : sT;
    const Eigen::VectorXd& t = source_half ? tS : tT;
    Eigen::VectorXd value = (1 - w) * s + w * t;
    for (Index v = 0; v < value.size(); ++v)
      if (value(v) == 0.0) value(v) = 1e-300;  // zero counts as outside (zero_set.hpp)
    surfaces.push_back(level_set(source_half ? source_cells : target_cells, source_half ? PS : PT, value));
  }
  surfaces.push_back({VT, FT});
  std::vector<double> travelled{0.0};
  for (size_t i = 0; i + 1 < surfaces.size(); ++i) travelled.push_back(travelled.back() + two_sided(surfaces[i], surfaces[i + 1]));
  BlendSchedule schedule;
  const double total = travelled.back();
  for (int i = 0; i <= samples; ++i) {
    const double w = static_cast<double>(i) / samples;
    const double moved = total > 0 ? travelled[i] / total : w;
    schedule.w.push_back(w);
    schedule.u.push_back(kFollowMotion * moved + (1 - kFollowMotion) * w);
  }
  return schedule;
}

}  // namespace animanifold::morph_field
