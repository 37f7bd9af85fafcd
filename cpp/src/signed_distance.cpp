#include "signed_distance.hpp"

#include "animanifold/errors.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

namespace animanifold {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, Kernel, CGAL::Default, AabbTree>;
}  // namespace

struct SignedDistance::Tree {
  Mesh mesh;
  PointMatrix V;
  SimplexMatrix F;
  std::unique_ptr<AabbTree> tree;
  std::unique_ptr<Side> side;
};

SignedDistance::SignedDistance(const PointMatrix& V, const SimplexMatrix& F) : tree_(std::make_unique<Tree>()) {
  if (V.cols() != 3 || F.cols() != 3) fail<InputError>("signed distance needs a triangle mesh in R^3");
  Tree& t = *tree_;
  t.V = V, t.F = F;
  std::vector<Mesh::Vertex_index> vertex(V.rows());
  for (Index v = 0; v < V.rows(); ++v) vertex[v] = t.mesh.add_vertex(Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)));
  for (Index f = 0; f < F.rows(); ++f)
    if (t.mesh.add_face(vertex[F(f, 0)], vertex[F(f, 1)], vertex[F(f, 2)]) == Mesh::null_face())
      fail<InputError>("face ", f, " cannot join the surface (not a manifold, or inconsistently oriented)");
  t.tree = std::make_unique<AabbTree>(faces(t.mesh).first, faces(t.mesh).second, t.mesh);
  // Built now, not at the first query: queries run in parallel.
  t.tree->accelerate_distance_queries();
  t.tree->build();
  t.side = std::make_unique<Side>(*t.tree);
}

SignedDistance::~SignedDistance() = default;
SignedDistance::SignedDistance(SignedDistance&&) noexcept = default;
SignedDistance& SignedDistance::operator=(SignedDistance&&) noexcept = default;

SurfaceProjection SignedDistance::operator()(const PointMatrix& points) const {
  const Tree& t = *tree_;
  SurfaceProjection out;
  const Index n = static_cast<Index>(points.rows());
  out.distance.resize(n);
  out.face.resize(n);
  out.barycentric.resize(n, 3);
#pragma omp parallel for schedule(dynamic, 256)
  for (Index p = 0; p < n; ++p) {
    const Kernel::Point_3 q(points(p, 0), points(p, 1), points(p, 2));
    const auto [closest, face] = t.tree->closest_point_and_primitive(q);
    const double distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(q, closest)));
    const bool inside = (*t.side)(q) != CGAL::ON_UNBOUNDED_SIDE;
    out.distance(p) = inside ? -distance : distance;
    const Index f = static_cast<Index>(face.idx());
    out.face(p) = f;
    // The closest point in the face's corners (faces were added in order).
    const Eigen::Vector3d a = t.V.row(t.F(f, 0)), b = t.V.row(t.F(f, 1)), c = t.V.row(t.F(f, 2));
    const Eigen::Vector3d x(closest.x(), closest.y(), closest.z());
    const Eigen::Vector3d n3 = (b - a).cross(c - a);
    const double area2 = n3.squaredNorm();
    if (area2 > 0) {
      const double wa = (c - b).cross(x - b).dot(n3) / area2, wb = (a - c).cross(x - c).dot(n3) / area2;
      out.barycentric.row(p) << wa, wb, 1.0 - wa - wb;
    } else {
      out.barycentric.row(p) << 1.0, 0.0, 0.0;
    }
  }
  return out;
}

Eigen::VectorXd SignedDistance::distances(const PointMatrix& points) const { return (*this)(points).distance; }

Eigen::Array<bool, Eigen::Dynamic, 1> SignedDistance::inside(const PointMatrix& points) const {
  const Tree& t = *tree_;
  Eigen::Array<bool, Eigen::Dynamic, 1> out(points.rows());
#pragma omp parallel for schedule(dynamic, 256)
  for (Index p = 0; p < static_cast<Index>(points.rows()); ++p)
    out(p) = (*t.side)(Kernel::Point_3(points(p, 0), points(p, 1), points(p, 2))) != CGAL::ON_UNBOUNDED_SIDE;
  return out;
}

}  // namespace animanifold
