// Exact orientation of a simplex (see exact_orientation.hpp).
#include "animanifold/exact_orientation.hpp"

#include "animanifold/errors.hpp"

#include <CGAL/Epick_d.h>
#include <Eigen/LU>
#include <array>
#include <cmath>

namespace animanifold {

namespace {

template <int D>
int sign_in(const PointMatrix& points, const Index* corners) {
  using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
  using Point = typename Kernel::Point_d;
  std::array<Point, D + 1> p;
  for (int i = 0; i <= D; ++i) p[i] = Point(points.row(corners[i]).data(), points.row(corners[i]).data() + D);
  const auto sign = Kernel().orientation_d_object()(p.begin(), p.end());
  return sign == CGAL::POSITIVE ? 1 : sign == CGAL::NEGATIVE ? -1 : 0;
}

// A semi-static filter in front of sign_in(): CGAL's Epick_d filters with
// interval arithmetic only, which made the exact orientation of the field
// morph's two transition slabs (2.2M 4-simplices) most of its certificate's
// 0.75 s. The determinant of the edges in doubles is off from the exact one
// by less than about (D + 4) * 2^-53 times the permanent of their absolute
// values (the rounded differences included), which is at most D! times the
// product of each column's largest entry; kFilterBound is that bound for
// D <= 4 with a margin of 40. Past it the sign is the exact one; within it
// (a simplex flat to rounding, or overflow) the exact predicate decides.
constexpr double kFilterBound = 1e-12;

template <int D>
int filtered_sign(const PointMatrix& points, const Index* corners) {
  Eigen::Matrix<double, D, D> edges;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) edges(i, j) = points(corners[i + 1], j) - points(corners[0], j);
  double bound = kFilterBound;
  for (int j = 0; j < D; ++j) bound *= edges.col(j).cwiseAbs().maxCoeff();
  const double det = edges.determinant();
  if (std::isfinite(bound) && bound > 0 && std::abs(det) > bound) return det > 0 ? 1 : -1;
  return sign_in<D>(points, corners);
}

}  // namespace

int exact_orientation(const PointMatrix& points, const Index* corners) {
  switch (points.cols()) {
    case 2: return filtered_sign<2>(points, corners);
    case 3: return filtered_sign<3>(points, corners);
    case 4: return filtered_sign<4>(points, corners);
    default: fail<InputError>("exact orientation is built for R^2 to R^4, got R^", points.cols());
  }
  return 0;
}

}  // namespace animanifold
