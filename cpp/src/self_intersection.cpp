#include "animanifold/self_intersection.hpp"

#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"
#include "animanifold/validation.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>
#include <Eigen/Dense>
#include <algorithm>
#include <iterator>

namespace animanifold {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// How far the triangle `b` (rows of V) passes through the plane of `a`: the
// smaller of how far its corners reach on either side (0 when all lie on
// one side: it touches the plane at most).
double depth_through(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  Eigen::Vector3d normal = (a.row(1) - a.row(0)).cross(a.row(2) - a.row(0));
  const double length = normal.norm();
  if (length == 0) return 0.0;
  normal /= length;
  double above = 0, below = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = (b.row(i) - a.row(0)).dot(normal.transpose());
    above = std::max(above, d), below = std::max(below, -d);
  }
  return std::min(above, below);
}

// The widest the overlap of two triangles lying in one plane (to
// `tolerance`) gets, in the plane of `a`: twice its area over its perimeter.
double coplanar_overlap(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const Eigen::Vector3d u = (a.row(1) - a.row(0)).normalized();
  const Eigen::Vector3d normal = (a.row(1) - a.row(0)).cross(a.row(2) - a.row(0)).normalized();
  const Eigen::Vector3d w = normal.cross(u);
  auto flat = [&](const Eigen::Matrix3d& t) {
    std::vector<Eigen::Vector2d> p;
    for (int i = 0; i < 3; ++i) p.emplace_back((t.row(i) - a.row(0)).dot(u.transpose()), (t.row(i) - a.row(0)).dot(w.transpose()));
    const Eigen::Vector2d e1 = p[1] - p[0], e2 = p[2] - p[0];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0) std::swap(p[1], p[2]);
    return p;
  };
  const std::vector<Eigen::Vector2d> clipper = flat(a);
  std::vector<Eigen::Vector2d> polygon = flat(b);
  for (int e = 0; e < 3 && !polygon.empty(); ++e) {  // Sutherland–Hodgman against each edge of a
    const Eigen::Vector2d p = clipper[e], q = clipper[(e + 1) % 3];
    auto side = [&](const Eigen::Vector2d& x) { return (q.x() - p.x()) * (x.y() - p.y()) - (q.y() - p.y()) * (x.x() - p.x()); };
    std::vector<Eigen::Vector2d> kept;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d x = polygon[i], y = polygon[(i + 1) % polygon.size()];
      const double sx = side(x), sy = side(y);
      if (sx >= 0) kept.push_back(x);
      if ((sx >= 0) != (sy >= 0)) kept.push_back(x + sx / (sx - sy) * (y - x));
    }
    polygon = std::move(kept);
  }
  if (polygon.size() < 3) return 0.0;
  double area = 0, perimeter = 0;  // (twice the area, from its first corner: a tiny polygon far out stays exact)
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d x = polygon[i] - polygon[0], y = polygon[(i + 1) % polygon.size()] - polygon[0];
    area += x.x() * y.y() - y.x() * x.y();
    perimeter += (y - x).norm();
  }
  return perimeter > 0 ? std::abs(area) / perimeter : 0.0;
}

// How far two crossing triangles pass through each other: the smaller of
// their depths through each other's planes; for two in one plane (to
// `tolerance`), how wide their overlap is.
double interpenetration(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, double tolerance) {
  const double depth = std::min(depth_through(a, b), depth_through(b, a));
  if (depth > tolerance) return depth;
  auto off_plane = [](const Eigen::Matrix3d& t, const Eigen::Matrix3d& other) {
    const Eigen::Vector3d normal = (t.row(1) - t.row(0)).cross(t.row(2) - t.row(0)).normalized();
    double far = 0;
    for (int i = 0; i < 3; ++i) far = std::max(far, std::abs((other.row(i) - t.row(0)).dot(normal.transpose())));
    return far;
  };
  if (off_plane(a, b) <= tolerance && off_plane(b, a) <= tolerance)
    return std::max(coplanar_overlap(a, b), coplanar_overlap(b, a));
  return depth;
}

std::vector<std::pair<Index, Index>> triangle_pairs(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs,
                                                    double tolerance) {
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vertex(V.rows());
  for (Index v = 0; v < V.rows(); ++v) vertex[v] = mesh.add_vertex(Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)));
  std::vector<Index> face_id;
  for (Index f = 0; f < F.rows(); ++f) {
    if (mesh.add_face(vertex[F(f, 0)], vertex[F(f, 1)], vertex[F(f, 2)]) == Mesh::null_face())
      fail<NotManifoldError>("face ", f, " cannot join the surface (the shape is not a manifold there)");
    face_id.push_back(f);
  }
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  translating_cgal_failures("finding the self-intersections of a surface of " + std::to_string(F.rows()) + " faces",
                            [&] {
                              CGAL::Polygon_mesh_processing::self_intersections(mesh.faces(), mesh,
                                                                                std::back_inserter(pairs));
                            });
  std::vector<std::pair<Index, Index>> out;
  auto corners = [&](Index f) {
    Eigen::Matrix3d t;
    for (int i = 0; i < 3; ++i) t.row(i) = V.row(F(f, i)).head<3>();
    return t;
  };
  for (const auto& [a, b] : pairs) {
    const Index fa = face_id[static_cast<std::size_t>(a)], fb = face_id[static_cast<std::size_t>(b)];
    if (tolerance > 0 && interpenetration(corners(fa), corners(fb), tolerance) <= tolerance) continue;
    out.emplace_back(std::min(fa, fb), std::max(fa, fb));
  }
  std::sort(out.begin(), out.end());
  if (max_pairs && out.size() > max_pairs) out.resize(max_pairs);
  return out;
}

// How far two crossing segments pass through each other (the 2D analogue
// of interpenetration: depths through each other's lines, or the length of
// their overlap when both lie on one line to `tolerance`).
double segment_interpenetration(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1, const Eigen::Vector2d& b0,
                                const Eigen::Vector2d& b1, double tolerance) {
  auto depth = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& x, const Eigen::Vector2d& y,
                  double* far) {
    const Eigen::Vector2d d = q - p;
    const double length = d.norm();
    if (length == 0) return *far = 0.0;
    const double sx = (d.x() * (x.y() - p.y()) - d.y() * (x.x() - p.x())) / length;
    const double sy = (d.x() * (y.y() - p.y()) - d.y() * (y.x() - p.x())) / length;
    *far = std::max(std::abs(sx), std::abs(sy));
    return std::min(std::max({sx, sy, 0.0}), std::max({-sx, -sy, 0.0}));
  };
  double far_b = 0, far_a = 0;
  const double through = std::min(depth(a0, a1, b0, b1, &far_b), depth(b0, b1, a0, a1, &far_a));
  if (through > tolerance || far_a > tolerance || far_b > tolerance) return through;
  const Eigen::Vector2d d = (a1 - a0).normalized();  // on one line: the length they share
  const double lo = std::max(0.0, std::min((b0 - a0).dot(d), (b1 - a0).dot(d)));
  const double hi = std::min((a1 - a0).norm(), std::max((b0 - a0).dot(d), (b1 - a0).dot(d)));
  return std::max(0.0, hi - lo);
}

std::vector<std::pair<Index, Index>> segment_pairs(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs,
                                                   double tolerance) {
  std::vector<std::pair<Index, Index>> out;
  auto point = [&](Index v) { return Kernel::Point_2(V(v, 0), V(v, 1)); };
  for (Index a = 0; a < F.rows(); ++a)
    for (Index b = a + 1; b < F.rows(); ++b) {
      const Kernel::Segment_2 sa(point(F(a, 0)), point(F(a, 1))), sb(point(F(b, 0)), point(F(b, 1)));
      if (!CGAL::do_intersect(sa, sb)) continue;
      // Neighbours touch at their shared corner, and only there unless they overlap (collinear, folding back).
      const bool shared = F(a, 0) == F(b, 1) || F(a, 1) == F(b, 0) || F(a, 0) == F(b, 0) || F(a, 1) == F(b, 1);
      if (shared) {
        const Index corner = (F(a, 0) == F(b, 0) || F(a, 0) == F(b, 1)) ? F(a, 0) : F(a, 1);
        const Index other_a = F(a, 0) == corner ? F(a, 1) : F(a, 0), other_b = F(b, 0) == corner ? F(b, 1) : F(b, 0);
        const bool folds = CGAL::collinear(point(corner), point(other_a), point(other_b)) &&
                           CGAL::angle(point(other_a), point(corner), point(other_b)) == CGAL::ACUTE;
        if (!folds) continue;
      }
      if (tolerance > 0 &&
          segment_interpenetration(V.row(F(a, 0)).head<2>(), V.row(F(a, 1)).head<2>(), V.row(F(b, 0)).head<2>(),
                                   V.row(F(b, 1)).head<2>(), tolerance) <= tolerance)
        continue;
      out.emplace_back(a, b);
      if (max_pairs && out.size() >= max_pairs) return out;
    }
  return out;
}

}  // namespace

std::vector<std::pair<Index, Index>> self_intersections(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs,
                                                        double tolerance) {
  check_indices(F, V.rows(), "face");
  if (V.cols() == 3 && F.cols() == 3) return triangle_pairs(V, F, max_pairs, tolerance);
  if (V.cols() == 2 && F.cols() == 2) return segment_pairs(V, F, max_pairs, tolerance);
  fail<InputError>("self-intersection is checked for triangles in R^3 and segments in R^2, got ", F.cols(),
                   "-corner faces in R^", V.cols());
}

}  // namespace animanifold
