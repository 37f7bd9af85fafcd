#include "animanifold/validation.hpp"
#include "animanifold/coordinate_bound.hpp"

#include "animanifold/errors.hpp"

#include <cmath>
#include <limits>

namespace animanifold {

void check_indices(const Eigen::Ref<const SimplexMatrix>& rows, Eigen::Index count, const char* what) {
  // The usual case, all in range, in two vectorised passes; the loop below names the first offender.
  if (rows.size() == 0 || (rows.minCoeff() >= 0 && rows.maxCoeff() < count)) return;
  for (Eigen::Index r = 0; r < rows.rows(); ++r)
    for (Eigen::Index c = 0; c < rows.cols(); ++c) {
      const Index v = rows(r, c);
      if (v >= 0 && v < count) continue;
      if (count == 0) fail<InputError>(what, " ", r, " refers to vertex ", v, ", but there are no vertices");
      fail<InputError>(what, " ", r, " refers to vertex ", v, ", outside 0..", count - 1);
    }
}

Index checked_index_count(std::int64_t count, const char* what) {
  constexpr std::int64_t largest = std::numeric_limits<Index>::max();
  if (count < 0 || count > largest)
    fail<InputError>(what, ": ", count, " is more than a 32-bit index can address (at most ", largest, ")");
  return static_cast<Index>(count);
}

void check_coordinates(const Eigen::Ref<const PointMatrix>& points, const char* what, double bound) {
  // The usual case in one vectorised pass (a NaN compares false, so it fails it too); the loop
  // below names the offender.
  if ((points.array().abs() <= bound).all()) return;
  for (Eigen::Index p = 0; p < points.rows(); ++p)
    for (Eigen::Index c = 0; c < points.cols(); ++c) {
      const double x = points(p, c);
      if (!std::isfinite(x)) fail<InputError>(what, " ", p, " is not finite");
      if (std::abs(x) > bound) fail<InputError>(what, " ", p, " has a coordinate of ", x, ", beyond +-", bound);
    }
}

}  // namespace animanifold
