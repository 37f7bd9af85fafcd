#include "animanifold/surface_distance.hpp"

#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"
#include "animanifold/validation.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace animanifold {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length = ab.squaredNorm();
  const double s = length > 0 ? std::clamp((p - a).dot(ab) / length, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

}  // namespace

Eigen::VectorXd distances_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces) {
  const int d = static_cast<int>(vertices.cols());
  Eigen::VectorXd out = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  if (points.rows() == 0 || faces.rows() == 0) return out;
  if (points.cols() != d || faces.cols() != d)
    fail<InputError>("distance to a surface needs matching dimensions (points ", points.cols(), "D, surface ", d, "D)");
  check_indices(faces, vertices.rows(), "face");
  if (d == 3) {
    std::vector<Triangle> triangles;
    triangles.reserve(faces.rows());
    auto at = [&](Index v) { return Kernel::Point_3(vertices(v, 0), vertices(v, 1), vertices(v, 2)); };
    for (Index f = 0; f < faces.rows(); ++f) {
      const Triangle t(at(faces(f, 0)), at(faces(f, 1)), at(faces(f, 2)));
      if (!t.is_degenerate()) triangles.push_back(t);
    }
    if (triangles.empty()) return out;
    translating_cgal_failures(
        "measuring " + std::to_string(points.rows()) + " distances to " + std::to_string(triangles.size()) + " triangles",
        [&] {
          Tree tree(triangles.begin(), triangles.end());
          tree.accelerate_distance_queries();
          for (Index p = 0; p < points.rows(); ++p)
            out(p) = std::sqrt(tree.squared_distance(Kernel::Point_3(points(p, 0), points(p, 1), points(p, 2))));
        });
    return out;
  }
  if (d == 2) {
    for (Index p = 0; p < points.rows(); ++p) {
      double best = std::numeric_limits<double>::infinity();
      for (Index f = 0; f < faces.rows(); ++f)
        best = std::min(best, segment_distance(points.row(p).transpose(), vertices.row(faces(f, 0)).transpose(),
                                               vertices.row(faces(f, 1)).transpose()));
      out(p) = best;
    }
    return out;
  }
  fail<InputError>("distance to a surface is defined in 2D and 3D, not ", d, "D");
}

double max_distance_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces) {
  if (points.rows() == 0) return 0.0;
  return distances_to_surface(points, vertices, faces).maxCoeff();
}

}  // namespace animanifold
