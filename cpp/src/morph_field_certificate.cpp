// The certificate that the field method's space-time triangulation is
// embedded (morph_field.hpp's certify_space_time).
#include "convex_cover.hpp"
#include "morph_field.hpp"

#include <algorithm>
#include <string>

namespace animanifold {

namespace {

// `points` (3D) copied into R^4 at `time`.
PointMatrix at_time(const PointMatrix& points, double time) {
  PointMatrix out(points.rows(), 4);
  out << points, Eigen::VectorXd::Constant(points.rows(), time);
  return out;
}

// The slab from an end's refined cells to the fill's end facet in R^4, at
// the layers' times (transition_slab's ids: the refined layer's points, then
// the fill's).
ConvexCover transition_cover(const SpaceTimeTriangulation::Side& side) {
  const Index n = static_cast<Index>(side.points.rows());
  const size_t layers = side.times.size();
  PointMatrix points(n + side.plain, 4);
  points << at_time(side.points, side.times[layers - 2]), at_time(side.points.topRows(side.plain), side.times[layers - 1]);
  return check_convex_cover(points, side.transition);
}

bool strictly_monotone(const std::vector<double>& times, bool increasing) {
  for (size_t i = 1; i < times.size(); ++i)
    if (increasing ? !(times[i] > times[i - 1]) : !(times[i] < times[i - 1])) return false;
  return true;
}

}  // namespace

SpaceTimeCertificate certify_space_time(const SpaceTimeTriangulation& space_time) {
  const auto& S = space_time.source;
  const auto& T = space_time.target;
  SpaceTimeCertificate out;
  if (S.times.size() < 2 || T.times.size() < 2 || !strictly_monotone(S.times, true) ||
      !strictly_monotone(T.times, false) || !(S.times.back() < T.times.back())) {
    out.failure = "the layers' times do not increase from t0 to t1";
    return out;
  }
  if (space_time.flat_crossed_simplices > 0) {
    out.failure = std::to_string(space_time.flat_crossed_simplices) +
                  " simplices the zero set passes through are flat but for rounding";
    return out;
  }
  auto check = [&](const char* part, const ConvexCover& cover) {
    if (!out.failure.empty() || cover.covers_once()) return;
    out.failure = std::string(part) + " does not tile its region once (" + cover.failure() + ")";
  };
  check("the source's cells", check_convex_cover(S.points, S.cells));
  check("the target's cells", check_convex_cover(T.points, T.cells));
  check("the source's transition slab", transition_cover(S));
  check("the target's transition slab", transition_cover(T));
  out.embedded = out.failure.empty();
  return out;
}

}  // namespace animanifold
