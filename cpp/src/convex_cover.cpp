#include "convex_cover.hpp"

#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/exact_orientation.hpp"
#include "animanifold/threads.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

namespace animanifold {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

// The summed volumes must match the region's to this share: the count k of
// simplices over a point is an integer, so anything but rounding away from
// 1 means a gap or a second layer.
constexpr double kVolumeTolerance = 1e-6;

// The convex hull of a point set in R^3: its triangles, and per hull vertex
// (by its exact coordinates) the triangles around it.
struct Hull {
  std::vector<std::array<Point, 3>> triangles;
  std::map<std::array<double, 3>, std::vector<size_t>> around;
  double volume = 0;

  explicit Hull(const std::vector<Point>& points) {
    CGAL::Surface_mesh<Point> mesh;
    CGAL::convex_hull_3(points.begin(), points.end(), mesh);
    for (const auto f : mesh.faces()) {
      std::array<Point, 3> corners;
      int c = 0;
      for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) corners[c++] = mesh.point(v);
      for (const Point& p : corners) around[{p.x(), p.y(), p.z()}].push_back(triangles.size());
      // The divergence theorem: the hull's volume from its outward triangles.
      volume += CGAL::determinant(corners[0].x(), corners[0].y(), corners[0].z(), corners[1].x(), corners[1].y(),
                                  corners[1].z(), corners[2].x(), corners[2].y(), corners[2].z()) / 6.0;
      triangles.push_back(corners);
    }
  }

  // Whether all of `points` lie in the plane of one hull triangle around one
  // of them (exactly).
  bool on_boundary(const std::vector<Point>& points) const {
    for (const Point& p : points) {
      const auto found = around.find({p.x(), p.y(), p.z()});
      if (found == around.end()) continue;
      for (const size_t t : found->second) {
        const auto& [a, b, c] = triangles[t];
        bool all = true;
        for (const Point& q : points) all = all && CGAL::orientation(a, b, c, q) == CGAL::COPLANAR;
        if (all) return true;
      }
    }
    return false;
  }
};

Point spatial(const PointMatrix& points, Index v) { return {points(v, 0), points(v, 1), points(v, 2)}; }

// The region the used points span: the hull of their first three
// coordinates, and in R^4 the interval of their times.
struct Region {
  Hull hull;
  double first = 0, last = 0;

  double volume() const { return last > first ? hull.volume * (last - first) : hull.volume; }

  // Whether the facet (rows of `points`) lies on the region's boundary: in
  // R^4 at its first or last time, or over the hull's boundary.
  bool on_boundary(const PointMatrix& points, const Index* facet, int corners) const {
    std::vector<Point> spatial_corners;
    bool at_first = points.cols() == 4, at_last = at_first;
    for (int c = 0; c < corners; ++c) {
      spatial_corners.push_back(spatial(points, facet[c]));
      if (points.cols() == 4) at_first = at_first && points(facet[c], 3) == first, at_last = at_last && points(facet[c], 3) == last;
    }
    return at_first || at_last || hull.on_boundary(spatial_corners);
  }
};

Region region_of(const PointMatrix& points, const std::vector<bool>& used) {
  std::vector<Point> spatial_points;
  double first = INFINITY, last = -INFINITY;
  for (Index v = 0; v < points.rows(); ++v) {
    if (!used[v]) continue;
    spatial_points.push_back(spatial(points, v));
    if (points.cols() == 4) first = std::min(first, points(v, 3)), last = std::max(last, points(v, 3));
  }
  return {Hull(spatial_points), points.cols() == 4 ? first : 0.0, points.cols() == 4 ? last : 0.0};
}

// The simplices' summed volumes: each written into its own entry, then
// summed in order, the same on any thread count.
template <int D>
double volume_sum(const PointMatrix& points, const SimplexMatrix& simplices) {
  double factorial = 1;
  for (int i = 2; i <= D; ++i) factorial *= i;
  Eigen::VectorXd volumes(simplices.rows());
#pragma omp parallel for schedule(static) num_threads(thread_count())
  for (Index s = 0; s < simplices.rows(); ++s) {
    Eigen::Matrix<double, D, D> edges;  // fixed size: a dynamic one per simplex costs more than its determinant
    for (int i = 0; i < D; ++i) edges.row(i) = points.row(simplices(s, i + 1)) - points.row(simplices(s, 0));
    volumes(s) = edges.determinant() / factorial;
  }
  return volumes.sum();
}

}  // namespace

bool ConvexCover::covers_once() const {
  return not_positive == 0 && unmatched_facets == 0 && repeated_vertices == 0 && stray_boundary_facets == 0 &&
         std::abs(volume_ratio - 1.0) <= kVolumeTolerance;
}

std::string ConvexCover::failure() const {
  if (covers_once()) return "";
  std::ostringstream out;
  out << simplices << " simplices:";
  if (not_positive) out << " " << not_positive << " flat or inverted;";
  if (repeated_vertices) out << " " << repeated_vertices << " repeat a vertex;";
  if (unmatched_facets) out << " " << unmatched_facets << " facets not shared by exactly two on opposite sides;";
  if (stray_boundary_facets) out << " " << stray_boundary_facets << " boundary facets inside the region;";
  out << " volumes sum to " << volume_ratio << " times the region's";
  return out.str();
}

ConvexCover check_convex_cover(const PointMatrix& points, const SimplexMatrix& simplices) {
  const int d = static_cast<int>(points.cols());
  if (d != 3 && d != 4) fail<InputError>("a convex cover is checked in R^3 or R^4, got R^", d);
  if (simplices.rows() > 0 && simplices.cols() != d + 1)
    fail<InputError>("simplices in R^", d, " have ", d + 1, " corners, got ", simplices.cols());
  ConvexCover out;
  out.simplices = simplices.rows();
  if (simplices.rows() == 0) return out;
  std::vector<bool> used(points.rows(), false);
  for (Index s = 0; s < simplices.rows(); ++s)
    for (int c = 0; c <= d; ++c) {
      const Index v = simplices(s, c);
      if (v < 0 || v >= points.rows()) fail<InputError>("simplex ", s, " refers to point ", v, ", outside 0..", points.rows() - 1);
      used[v] = true;
    }
  std::int64_t not_positive = 0;
#pragma omp parallel for schedule(static) reduction(+ : not_positive) num_threads(thread_count())
  for (Index s = 0; s < simplices.rows(); ++s) not_positive += exact_orientation(points, simplices.row(s).data()) <= 0;
  out.not_positive = not_positive;
  SimplexMatrix boundary;
  const ManifoldReport manifold = check_manifold(simplices, &boundary);
  out.unmatched_facets = manifold.nonmanifold_facets + manifold.misoriented_facets;
  out.repeated_vertices = manifold.degenerate_simplices;
  const Region region = region_of(points, used);
  for (Index f = 0; f < boundary.rows(); ++f)
    out.stray_boundary_facets += !region.on_boundary(points, boundary.row(f).data(), d);
  const double volume = region.volume();
  out.volume_ratio = volume > 0 ? (d == 3 ? volume_sum<3>(points, simplices) : volume_sum<4>(points, simplices)) / volume
                                : INFINITY;
  return out;
}

}  // namespace animanifold
