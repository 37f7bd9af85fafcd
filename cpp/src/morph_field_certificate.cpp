// The certificate that the field method's space-time triangulation is
// embedded (morph_field.hpp's certify_space_time).
#include "convex_cover.hpp"
#include "morph_field.hpp"

#include "animanifold/errors.hpp"

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
ConvexCover transition_cover(const PointMatrix& side_points, Index plain, const SimplexMatrix& transition,
                             const std::vector<double>& times) {
  const Index n = static_cast<Index>(side_points.rows());
  const size_t layers = times.size();
  PointMatrix points(n + plain, 4);
  points << at_time(side_points, times[layers - 2]), at_time(side_points.topRows(plain), times[layers - 1]);
  return check_convex_cover(points, transition);
}

std::string failure_of(const ConvexCover& cover) { return cover.covers_once() ? "" : cover.failure(); }

bool strictly_monotone(const std::vector<double>& times, bool increasing) {
  for (size_t i = 1; i < times.size(); ++i)
    if (increasing ? !(times[i] > times[i - 1]) : !(times[i] < times[i - 1])) return false;
  return true;
}

}  // namespace

SpaceTimeCertificate certify_space_time(const SpaceTimeTriangulation& space_time,
                                        const std::array<SideCover, 2>* covers) {
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
  auto cover_of = [&](const SpaceTimeTriangulation::Side& side, int index) {
    return covers ? (*covers)[index] : check_side_cover(side.points, side.plain, side.cells, side.transition, side.times);
  };
  const SideCover source = cover_of(S, 0), target = cover_of(T, 1);
  auto check = [&](const char* part, const std::string& failure) {
    if (!out.failure.empty() || failure.empty()) return;
    out.failure = std::string(part) + " does not tile its region once (" + failure + ")";
  };
  check("the source's cells", source.cells);
  check("the target's cells", target.cells);
  check("the source's transition slab", source.transition);
  check("the target's transition slab", target.transition);
  out.embedded = out.failure.empty();
  return out;
}

std::string check_cells_cover(const PointMatrix& points, const SimplexMatrix& cells) {
  return failure_of(check_convex_cover(points, cells));
}

std::string check_transition_cover(const PointMatrix& points, Index plain, const SimplexMatrix& transition,
                                   const std::vector<double>& times) {
  if (times.size() < 2)
    fail<InputError>("a side of the space-time triangulation has ", times.size(), " layers, not 2 or more");
  return failure_of(transition_cover(points, plain, transition, times));
}

SideCover check_side_cover(const PointMatrix& points, Index plain, const SimplexMatrix& cells,
                           const SimplexMatrix& transition, const std::vector<double>& times) {
  if (times.size() < 2)
    fail<InputError>("a side of the space-time triangulation has ", times.size(), " layers, not 2 or more");
  return {check_cells_cover(points, cells), check_transition_cover(points, plain, transition, times)};
}

}  // namespace animanifold
