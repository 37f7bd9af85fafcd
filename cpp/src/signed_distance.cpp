#include "signed_distance.hpp"

#include "animanifold/coordinate_bound.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"
#include "cgal_failures.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
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
  check_coordinates(V, "the surface's vertex", kMaxDerivedCoordinate);
  Tree& t = *tree_;
  t.V = V, t.F = F;
  std::vector<Mesh::Vertex_index> vertex(V.rows());
  for (Index v = 0; v < V.rows(); ++v) vertex[v] = t.mesh.add_vertex(Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)));
  for (Index f = 0; f < F.rows(); ++f)
    if (t.mesh.add_face(vertex[F(f, 0)], vertex[F(f, 1)], vertex[F(f, 2)]) == Mesh::null_face())
      fail<NotManifoldError>("face ", f, " cannot join the surface (not a manifold, or inconsistently oriented)");
  translating_cgal_failures("building the distance tree of a surface of " + std::to_string(F.rows()) + " faces", [&] {
    t.tree = std::make_unique<AabbTree>(faces(t.mesh).first, faces(t.mesh).second, t.mesh);
    // Built now, not at the first query: queries run in parallel.
    t.tree->accelerate_distance_queries();
    t.tree->build();
    t.side = std::make_unique<Side>(*t.tree);
  });
}

SignedDistance::~SignedDistance() = default;
SignedDistance::SignedDistance(SignedDistance&&) noexcept = default;
SignedDistance& SignedDistance::operator=(SignedDistance&&) noexcept = default;

namespace {

// The closest point of the tree's mesh to q: its distance, face and
// barycentric coordinates in the face's corners (faces were added in order).
// The distance from q to its closest point `found` on the tree's mesh, that
// point's face, and its barycentric coordinates in the face's corners (faces
// were added in order).
template <typename TreeState, typename Found>
void project_onto(const TreeState& t, const Kernel::Point_3& q, const Found& found, double* distance, Index* face,
                  Eigen::Ref<Eigen::RowVector3d> barycentric) {
  const auto& [closest, primitive] = found;
  *distance = std::sqrt(CGAL::to_double(CGAL::squared_distance(q, closest)));
  const Index f = static_cast<Index>(primitive.idx());
  *face = f;
  const Eigen::Vector3d a = t.V.row(t.F(f, 0)), b = t.V.row(t.F(f, 1)), c = t.V.row(t.F(f, 2));
  const Eigen::Vector3d x(closest.x(), closest.y(), closest.z());
  const Eigen::Vector3d n3 = (b - a).cross(c - a);
  const double area2 = n3.squaredNorm();
  if (area2 > 0) {
    const double wa = (c - b).cross(x - b).dot(n3) / area2, wb = (a - c).cross(x - c).dot(n3) / area2;
    barycentric << wa, wb, 1.0 - wa - wb;
  } else {
    barycentric << 1.0, 0.0, 0.0;
  }
}

template <typename TreeState>
void project(const TreeState& t, const Kernel::Point_3& q, double* distance, Index* face,
             Eigen::Ref<Eigen::RowVector3d> barycentric) {
  project_onto(t, q, t.tree->closest_point_and_primitive(q), distance, face, barycentric);
}

ClosestPoints sized(Index n) {
  ClosestPoints out;
  out.distance.resize(n);
  out.face.resize(n);
  out.barycentric.resize(n, 3);
  return out;
}

// The points' indices along a Morton (Z-order) curve over their bounding box,
// 10 bits per axis.
std::vector<Index> morton_order(const PointMatrix& points) {
  const Index n = static_cast<Index>(points.rows());
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), Index{0});
  if (n == 0) return order;
  const Eigen::RowVectorXd low = points.colwise().minCoeff(), high = points.colwise().maxCoeff();
  const double extent = std::max((high - low).maxCoeff(), 1e-300);
  auto spread = [](std::uint64_t x) {  // the bits of x, two zeros between each
    x &= 0x3ff;
    x = (x | (x << 16)) & 0x30000ff;
    x = (x | (x << 8)) & 0x300f00f;
    x = (x | (x << 4)) & 0x30c30c3;
    return (x | (x << 2)) & 0x9249249;
  };
  std::vector<std::uint64_t> code(n);
  for (Index p = 0; p < n; ++p) {
    std::uint64_t c = 0;
    for (int axis = 0; axis < 3; ++axis)
      c |= spread(static_cast<std::uint64_t>(1023.0 * (points(p, axis) - low(axis)) / extent)) << axis;
    code[p] = c;
  }
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return code[a] < code[b]; });
  return order;
}
}  // namespace

SurfaceProjection SignedDistance::operator()(const PointMatrix& points) const {
  check_coordinates(points, "query point", kMaxDerivedCoordinate);
  const Tree& t = *tree_;
  const Index n = static_cast<Index>(points.rows());
  SurfaceProjection out = sized(n);
#pragma omp parallel for schedule(dynamic, 256) num_threads(thread_count())
  for (Index p = 0; p < n; ++p) {
    const Kernel::Point_3 q(points(p, 0), points(p, 1), points(p, 2));
    double distance = 0;
    project(t, q, &distance, &out.face(p), out.barycentric.row(p));
    const bool inside = (*t.side)(q) != CGAL::ON_UNBOUNDED_SIDE;
    out.distance(p) = inside ? -distance : distance;
  }
  return out;
}

ClosestPoints SignedDistance::closest(const PointMatrix& points) const {
  check_coordinates(points, "query point", kMaxDerivedCoordinate);
  const Tree& t = *tree_;
  const Index n = static_cast<Index>(points.rows());
  ClosestPoints out = sized(n);
  // Queried in the order of a space-filling curve, each from its predecessor's
  // answer as the tree's hint: neighbours have nearby closest points, and the
  // tree's paths stay in cache.
  const std::vector<Index> order = morton_order(points);
  constexpr Index kChunk = 1024;
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
  for (Index chunk = 0; chunk < (n + kChunk - 1) / kChunk; ++chunk) {
    std::optional<std::pair<Kernel::Point_3, AabbTree::Primitive_id>> hint;
    for (Index k = chunk * kChunk; k < std::min(n, (chunk + 1) * kChunk); ++k) {
      const Index p = order[k];
      const Kernel::Point_3 q(points(p, 0), points(p, 1), points(p, 2));
      const auto found = hint ? t.tree->closest_point_and_primitive(q, *hint) : t.tree->closest_point_and_primitive(q);
      hint = found;
      project_onto(t, q, found, &out.distance(p), &out.face(p), out.barycentric.row(p));
    }
  }
  return out;
}

ClosestPoints closest_points(const PointMatrix& points, const PointMatrix& vertices, const SimplexMatrix& faces) {
  if (points.cols() != 3) fail<InputError>("closest points are found for points in R^3, got R^", points.cols());
  if (faces.rows() == 0) fail<InputError>("closest points need a mesh with faces");
  if (vertices.cols() != 3 || faces.cols() != 3) fail<InputError>("closest points need a triangle mesh in R^3");
  for (Index f = 0; f < faces.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (faces(f, c) < 0 || faces(f, c) >= vertices.rows())
        fail<InputError>("face ", f, " refers to vertex ", faces(f, c), ", outside 0..", vertices.rows() - 1);
  return SignedDistance(vertices, faces).closest(points);
}

Eigen::VectorXd SignedDistance::distances(const PointMatrix& points) const { return (*this)(points).distance; }

Eigen::Array<bool, Eigen::Dynamic, 1> SignedDistance::inside(const PointMatrix& points) const {
  check_coordinates(points, "query point", kMaxDerivedCoordinate);
  const Tree& t = *tree_;
  Eigen::Array<bool, Eigen::Dynamic, 1> out(points.rows());
#pragma omp parallel for schedule(dynamic, 256) num_threads(thread_count())
  for (Index p = 0; p < static_cast<Index>(points.rows()); ++p)
    out(p) = (*t.side)(Kernel::Point_3(points(p, 0), points(p, 1), points(p, 2))) != CGAL::ON_UNBOUNDED_SIDE;
  return out;
}

}  // namespace animanifold
