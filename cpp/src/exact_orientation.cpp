// Exact orientation of a simplex (see exact_orientation.hpp).
#include "animanifold/exact_orientation.hpp"

#include "animanifold/errors.hpp"

#include <CGAL/Epick_d.h>
#include <array>

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

}  // namespace

int exact_orientation(const PointMatrix& points, const Index* corners) {
  switch (points.cols()) {
    case 2: return sign_in<2>(points, corners);
    case 3: return sign_in<3>(points, corners);
    case 4: return sign_in<4>(points, corners);
    default: fail<InputError>("exact orientation is built for R^2 to R^4, got R^", points.cols());
  }
  return 0;
}

}  // namespace animanifold
