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
#include <memory>
#include <vector>

namespace animanifold {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using SearchTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length = ab.squaredNorm();
  const double s = length > 0 ? std::clamp((p - a).dot(ab) / length, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

}  // namespace

struct TriangleDistance::Tree {
  std::vector<Triangle> triangles;  // the tree refers to them
  std::unique_ptr<SearchTree> tree;
};

TriangleDistance::TriangleDistance(const PointMatrix& vertices, const SimplexMatrix& faces)
    : tree_(std::make_unique<Tree>()) {
  if (vertices.cols() != 3 || faces.cols() != 3)
    fail<InputError>("distance to a triangle mesh needs 3D points and triangles, got ", vertices.cols(), "D points and ",
                     faces.cols(), " corners");
  check_indices(faces, vertices.rows(), "face");
  auto at = [&](Index v) { return Kernel::Point_3(vertices(v, 0), vertices(v, 1), vertices(v, 2)); };
  tree_->triangles.reserve(faces.rows());
  for (Index f = 0; f < faces.rows(); ++f) {
    const Triangle t(at(faces(f, 0)), at(faces(f, 1)), at(faces(f, 2)));
    if (!t.is_degenerate()) tree_->triangles.push_back(t);
  }
  if (tree_->triangles.empty()) return;
  translating_cgal_failures("building the search tree of " + std::to_string(tree_->triangles.size()) + " triangles", [&] {
    tree_->tree = std::make_unique<SearchTree>(tree_->triangles.begin(), tree_->triangles.end());
    tree_->tree->accelerate_distance_queries();
  });
}

TriangleDistance::~TriangleDistance() = default;
TriangleDistance::TriangleDistance(TriangleDistance&&) noexcept = default;
TriangleDistance& TriangleDistance::operator=(TriangleDistance&&) noexcept = default;

Eigen::VectorXd TriangleDistance::operator()(const PointMatrix& points) const {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  if (points.rows() == 0 || !tree_->tree) return out;
  if (points.cols() != 3) fail<InputError>("distance to a triangle mesh needs 3D query points, got ", points.cols(), "D");
  translating_cgal_failures(
      "measuring " + std::to_string(points.rows()) + " distances to " + std::to_string(tree_->triangles.size()) + " triangles",
      [&] {
        for (Index p = 0; p < points.rows(); ++p)
          out(p) = std::sqrt(tree_->tree->squared_distance(Kernel::Point_3(points(p, 0), points(p, 1), points(p, 2))));
      });
  return out;
}

double TriangleDistance::farthest(const PointMatrix& points) const {
  if (points.rows() == 0) return 0.0;
  if (!tree_->tree) return std::numeric_limits<double>::infinity();
  if (points.cols() != 3)
    fail<InputError>("distance to a triangle mesh needs 3D query points, got ", points.cols(), "D");
  // A point is passed over only when a face lies within a radius a hair
  // short of the largest distance (in squares, a millionth): its own
  // distance is then below that one by more than the rounding of either
  // (a few units in the last place of the coordinates' squares), unless the
  // largest is below about 1e-5 of the coordinates, where rounding and not
  // distance tells the points apart. Every k-th point is measured first, so
  // that the largest is soon large.
  constexpr double kShorter = 1.0 - 1e-6;
  constexpr Index kFirstStride = 32;
  double largest = 0.0;  // squared
  translating_cgal_failures(
      "measuring the farthest of " + std::to_string(points.rows()) + " points from " +
          std::to_string(tree_->triangles.size()) + " triangles",
      [&] {
        auto at = [&](Index p) { return Kernel::Point_3(points(p, 0), points(p, 1), points(p, 2)); };
        for (Index p = 0; p < points.rows(); p += kFirstStride)
          largest = std::max(largest, tree_->tree->squared_distance(at(p)));
        for (Index p = 0; p < points.rows(); ++p) {
          if (p % kFirstStride == 0) continue;
          const Kernel::Point_3 q = at(p);
          if (largest > 0 && tree_->tree->do_intersect(Kernel::Sphere_3(q, kShorter * largest))) continue;
          largest = std::max(largest, tree_->tree->squared_distance(q));
        }
      });
  return std::sqrt(largest);
}

Eigen::VectorXd distances_to_surface(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces) {
  const int d = static_cast<int>(vertices.cols());
  Eigen::VectorXd out = Eigen::VectorXd::Constant(points.rows(), std::numeric_limits<double>::infinity());
  if (points.rows() == 0 || faces.rows() == 0) return out;
  if (points.cols() != d || faces.cols() != d)
    fail<InputError>("distance to a surface needs matching dimensions (points ", points.cols(), "D, surface ", d, "D)");
  check_indices(faces, vertices.rows(), "face");
  if (d == 3) return TriangleDistance(vertices, faces)(points);
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
  if (vertices.cols() == 3 && points.cols() == 3 && faces.cols() == 3)
    return TriangleDistance(vertices, faces).farthest(points);
  return distances_to_surface(points, vertices, faces).maxCoeff();
}

}  // namespace animanifold
