// Hole spaces and solid Booleans of closed triangle meshes in R^3: CGAL's
// convex_hull_3 and Polygon_mesh_processing corefinement on Surface_mesh with
// an exact-constructions kernel (Epeck), rounded to doubles at the end.
#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "hole_space_internal.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace animanifold::holes {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = ExactKernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Triangle = std::array<std::size_t, 3>;

// Faces whose height is below this fraction of the operand's size count as
// degenerate (see snap_nearly_degenerate).
constexpr double NEARLY_DEGENERATE = 1e-12;
// Four corners of a quad of C within this fraction of the size of one plane
// count as coplanar with the hull facets over them (see follow_hull).
constexpr double HULL_COPLANAR = 1e-9;

// Is `now` the triangle `before` with the same cyclic order (its corners
// possibly renumbered to copies of the same points)?
bool same_turn(const std::vector<Point>& points, const Triangle& before, const Triangle& now) {
  for (int r = 0; r < 3; ++r)
    if (points[before[0]] == points[now[r]] && points[before[1]] == points[now[(r + 1) % 3]] &&
        points[before[2]] == points[now[(r + 2) % 3]])
      return true;
  return false;
}

// Faces of nearly zero area (a vertex within `tolerance` of the line through
// the other two, which covers nearly coincident points too) are what slicing
// leaves where it cut a nearly flat simplex: exactly, they are thin folds
// that overlap their neighbours. Each cluster of such faces whose vertices lie
// along one line (within the tolerance) is made exactly collinear, its
// vertices projected onto the line through its two farthest points, so that
// remove_degenerate_faces can then collapse or flip them away exactly.
// Returns how many vertices moved (each by at most the tolerance).
std::size_t snap_nearly_degenerate(Mesh& mesh, double tolerance) {
  using Vertex = Mesh::Vertex_index;
  const auto at = [&](Vertex v) {
    const Point& p = mesh.point(v);
    return Eigen::Vector3d(rounded(p.x()), rounded(p.y()), rounded(p.z()));
  };
  std::vector<std::uint32_t> parent(mesh.num_vertices());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto root = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<bool> involved(mesh.num_vertices(), false);
  bool any = false;
  for (const auto f : mesh.faces()) {
    std::array<Vertex, 3> v;
    int c = 0;
    for (const auto w : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) v[c++] = w;
    const std::array<Eigen::Vector3d, 3> p{at(v[0]), at(v[1]), at(v[2])};
    int longest = 0;  // the corner opposite the longest edge
    double length = -1;
    for (int i = 0; i < 3; ++i)
      if (const double l = (p[(i + 2) % 3] - p[(i + 1) % 3]).norm(); l > length) length = l, longest = i;
    const Eigen::Vector3d a = p[(longest + 1) % 3], b = p[(longest + 2) % 3];
    const double height = length > 0 ? (p[longest] - a).cross(b - a).norm() / length : 0.0;
    if (height > tolerance || PMP::is_degenerate_triangle_face(f, mesh)) continue;
    any = true;
    for (int i = 0; i < 3; ++i) involved[v[i].idx()] = true;
    parent[root(v[1].idx())] = root(v[0].idx());
    parent[root(v[2].idx())] = root(v[0].idx());
  }
  if (!any) return 0;
  std::vector<std::vector<Vertex>> clusters(mesh.num_vertices());
  for (const auto v : mesh.vertices())
    if (involved[v.idx()]) clusters[root(v.idx())].push_back(v);
  std::size_t moved = 0;
  for (const std::vector<Vertex>& cluster : clusters) {
    if (cluster.empty()) continue;
    const auto farthest = [&](Vertex from) {
      Vertex best = from;
      double distance = -1;
      for (const Vertex v : cluster)
        if (const double d = (at(v) - at(from)).squaredNorm(); d > distance) distance = d, best = v;
      return best;
    };
    const Vertex p = farthest(cluster.front()), q = farthest(p);
    if (mesh.point(p) == mesh.point(q)) {  // all within the tolerance of one point
      for (const Vertex v : cluster)
        if (mesh.point(v) != mesh.point(p)) mesh.point(v) = mesh.point(p), ++moved;
      continue;
    }
    const Eigen::Vector3d a = at(p), direction = (at(q) - a).normalized();
    bool along = true;
    for (const Vertex v : cluster)
      along = along && (at(v) - a).cross(direction).norm() <= 2 * tolerance;
    if (!along) continue;  // not one line: left to the checks that follow
    const K::Line_3 line(mesh.point(p), mesh.point(q));
    for (const Vertex v : cluster)
      if (v != p && v != q) mesh.point(v) = line.projection(mesh.point(v)), ++moved;
  }
  return moved;
}

std::size_t count_degenerate(const Mesh& mesh) {
  std::size_t count = 0;
  for (const auto f : mesh.faces()) count += PMP::is_degenerate_triangle_face(f, mesh);
  return count;
}

// The exact Surface_mesh of an operand, or a BooleanError naming what CGAL
// could not work on. Faces of zero area (slices cut close to a vertex) are
// collapsed away first, since corefinement takes them for self-intersections.
Mesh exact_mesh(const Operand& s, bool check_self_intersection) {
  const ManifoldReport report = check_manifold(s.F);
  if (report.degenerate_simplices > 0)
    fail<BooleanError>(s.name, " has ", report.degenerate_simplices, " faces that repeat a vertex");
  if (report.boundary_facets > 0)
    fail<BooleanError>(s.name, " is not closed (", report.boundary_facets, " boundary edges)");
  if (report.nonmanifold_facets > 0)
    fail<BooleanError>(s.name, " is not a manifold (", report.nonmanifold_facets, " edges in more than two faces)");
  if (report.misoriented_facets > 0)
    fail<BooleanError>(s.name, " is not consistently oriented (", report.misoriented_facets,
                       " edges have both faces on the same side)");

  std::vector<Point> points;
  points.reserve(s.V.rows());
  for (Index v = 0; v < s.V.rows(); ++v) points.emplace_back(s.V(v, 0), s.V(v, 1), s.V(v, 2));
  std::vector<Triangle> triangles(s.F.rows());
  for (Index f = 0; f < s.F.rows(); ++f)
    triangles[f] = {static_cast<std::size_t>(s.F(f, 0)), static_cast<std::size_t>(s.F(f, 1)),
                    static_cast<std::size_t>(s.F(f, 2))};
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles)) {
    // Sheets that touch at a vertex only (a pinch): each gets its own copy of
    // the vertex. The orientation was checked above and must not change.
    const std::vector<Triangle> before = triangles;
    PMP::orient_polygon_soup(points, triangles);
    for (std::size_t f = 0; f < triangles.size(); ++f)
      if (!same_turn(points, before[f], triangles[f]))
        fail<BooleanError>(s.name, " cannot be oriented consistently around its pinched vertices (face ", f, ")");
  }
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, triangles, mesh);

  const double size = (s.V.colwise().maxCoeff() - s.V.colwise().minCoeff()).norm();
  snap_nearly_degenerate(mesh, NEARLY_DEGENERATE * size);
  if (count_degenerate(mesh) > 0) {
    PMP::remove_degenerate_faces(mesh);
    mesh.collect_garbage();
    if (const std::size_t left = count_degenerate(mesh); left > 0)
      fail<BooleanError>(s.name, " has ", left, " faces of zero area that cannot be collapsed away");
    if (!CGAL::is_closed(mesh)) fail<BooleanError>(s.name, " is no longer closed once its faces of zero area are collapsed");
    if (mesh.number_of_faces() == 0) fail<BooleanError>(s.name, " encloses no volume (every face has zero area)");
  }
  if (check_self_intersection && PMP::does_self_intersect(mesh)) fail<BooleanError>(s.name, " intersects itself");
  return mesh;
}

Solid to_solid(const Mesh& mesh) {
  Solid out;
  std::vector<Index> id(mesh.num_vertices(), -1);
  out.vertices.resize(static_cast<Index>(mesh.number_of_vertices()), 3);
  Index next = 0;
  for (const auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.vertices.row(next) << rounded(p.x()), rounded(p.y()), rounded(p.z());
    id[v.idx()] = next++;
  }
  out.faces.resize(static_cast<Index>(mesh.number_of_faces()), 3);
  Index row = 0;
  for (const auto f : mesh.faces()) {
    int c = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (c == 3) fail<std::logic_error>("a Boolean result has a face with more than three corners");
      out.faces(row, c++) = id[v.idx()];
    }
    ++row;
  }
  return out;
}

// Where C lies on its hull, a quad of C that is planar up to rounding may be
// split along the other diagonal than the hull's facets: the exact difference
// then keeps a sliver of rounding thickness there, and slivers of neighbouring
// quads touch along edges, so that the difference is not even a manifold.
// Flips every such edge of C (both its faces on hull vertices, the flipped
// edge a hull edge, the four corners within `tolerance` of one plane) so that
// C follows the hull's facets; the shape changes by the sliver only. With an
// infinite tolerance, every dent of C's triangulation between four hull
// vertices is flipped away. Returns the number of flips.
std::size_t follow_hull(Mesh& solid, const Mesh& hull, double tolerance) {
  using Vertex = Mesh::Vertex_index;
  std::map<Point, Vertex, K::Less_xyz_3> vertex_at;
  for (const auto v : solid.vertices()) vertex_at.emplace(solid.point(v), v);
  std::vector<bool> on_hull(solid.num_vertices(), false);
  std::set<std::pair<std::uint32_t, std::uint32_t>> hull_edges;
  for (const auto e : hull.edges()) {
    const auto a = vertex_at.find(hull.point(hull.vertex(e, 0))), b = vertex_at.find(hull.point(hull.vertex(e, 1)));
    if (a == vertex_at.end() || b == vertex_at.end()) continue;
    on_hull[a->second.idx()] = on_hull[b->second.idx()] = true;
    hull_edges.emplace(std::minmax(a->second.idx(), b->second.idx()));
  }
  const auto is_hull_edge = [&](Vertex a, Vertex b) { return hull_edges.count(std::minmax(a.idx(), b.idx())) > 0; };
  const auto at = [&](Vertex v) {
    const Point& p = solid.point(v);
    return Eigen::Vector3d(rounded(p.x()), rounded(p.y()), rounded(p.z()));
  };
  std::size_t flips = 0;
  for (bool again = true; again;) {
    again = false;
    for (const auto e : solid.edges()) {
      const auto h = solid.halfedge(e), o = solid.opposite(h);
      const Vertex a = solid.source(h), b = solid.target(h);
      const Vertex c = solid.target(solid.next(h)), d = solid.target(solid.next(o));
      if (!on_hull[a.idx()] || !on_hull[b.idx()] || !on_hull[c.idx()] || !on_hull[d.idx()]) continue;
      if (is_hull_edge(a, b) || !is_hull_edge(c, d) || c == d || CGAL::halfedge(c, d, solid).second) continue;
      const Eigen::Vector3d normal = (at(b) - at(a)).cross(at(c) - at(a));
      if (normal.norm() == 0 || std::abs(normal.normalized().dot(at(d) - at(a))) > tolerance) continue;
      CGAL::Euler::flip_edge(h, solid);
      ++flips, again = true;
    }
  }
  return flips;
}

// Shrinks the hull about the centroid of its vertices by HULL_SHRINK (see
// hole_space_internal.hpp), exactly.
void shrink_hull(Mesh& hull) {
  K::Vector_3 sum(0, 0, 0);
  for (const auto v : hull.vertices()) sum = sum + (hull.point(v) - CGAL::ORIGIN);
  const Point centre = CGAL::ORIGIN + sum / static_cast<double>(hull.number_of_vertices());
  const K::FT keep = 1.0 - HULL_SHRINK;
  for (const auto v : hull.vertices()) hull.point(v) = centre + (hull.point(v) - centre) * keep;
}

}  // namespace

bool intersects_itself_3d(const Operand& shape) {
  using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;  // exact predicates suffice
  std::vector<Inexact::Point_3> points;
  points.reserve(shape.V.rows());
  for (Index v = 0; v < shape.V.rows(); ++v) points.emplace_back(shape.V(v, 0), shape.V(v, 1), shape.V(v, 2));
  std::vector<Triangle> triangles(shape.F.rows());
  for (Index f = 0; f < shape.F.rows(); ++f)
    triangles[f] = {static_cast<std::size_t>(shape.F(f, 0)), static_cast<std::size_t>(shape.F(f, 1)),
                    static_cast<std::size_t>(shape.F(f, 2))};
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles)) PMP::orient_polygon_soup(points, triangles);
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles))
    fail<InputError>(shape.name, " is not a 2-manifold: its self-intersection cannot be tested");
  CGAL::Surface_mesh<Inexact::Point_3> mesh;
  PMP::polygon_soup_to_polygon_mesh(points, triangles, mesh);
  return PMP::does_self_intersect(mesh);
}

// Whether the closed surface is convex: connected, no edge bends outward
// (the far corner of each face's neighbour never above the face's plane;
// exact predicates), and no vertex has more than 2π of face angles around it
// (which a surface wound twice around a convex body would, at its branch
// points). A closed connected surface convex at every edge and vertex bounds
// a convex body, so its hole space is empty and both the self-intersection
// test and the hull's corefinement with it (every face of one in a face of
// the other: CGAL's slowest case) can be skipped. False when in doubt (an edge without exactly one opposite).
bool is_convex_surface(const Operand& shape) {
  using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;
  const Index n = shape.F.rows();
  std::map<std::pair<Index, Index>, Index> face_of_edge;  // directed edge -> its face
  for (Index f = 0; f < n; ++f)
    for (int c = 0; c < 3; ++c)
      if (!face_of_edge.emplace(std::pair{shape.F(f, c), shape.F(f, (c + 1) % 3)}, f).second) return false;
  auto point = [&](Index v) { return Inexact::Point_3(shape.V(v, 0), shape.V(v, 1), shape.V(v, 2)); };
  std::vector<Index> parent(n);
  for (Index f = 0; f < n; ++f) parent[f] = f;
  auto root = [&](Index f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  for (Index f = 0; f < n; ++f)
    for (int c = 0; c < 3; ++c) {
      const Index a = shape.F(f, c), b = shape.F(f, (c + 1) % 3);
      const auto opposite = face_of_edge.find({b, a});
      if (opposite == face_of_edge.end()) return false;
      const Index g = opposite->second;
      parent[root(f)] = root(g);
      Index far = -1;
      for (int k = 0; k < 3; ++k)
        if (shape.F(g, k) != a && shape.F(g, k) != b) far = shape.F(g, k);
      if (far < 0) return false;
      // (p, q, r, far) is negatively oriented where `far` lies behind the
      // face (p, q, r) seen from outside, as on a convex surface; positively
      // where the edge bends outward (and everywhere on an inside-out one).
      if (CGAL::orientation(point(shape.F(f, 0)), point(shape.F(f, 1)), point(shape.F(f, 2)), point(far)) ==
          CGAL::POSITIVE)
        return false;
    }
  for (Index f = 0; f < n; ++f)
    if (root(f) != root(0)) return false;
  std::vector<double> angle_sum(shape.V.rows(), 0.0);
  for (Index f = 0; f < n; ++f)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = shape.V.row(shape.F(f, c)).transpose();
      const Eigen::Vector3d u = shape.V.row(shape.F(f, (c + 1) % 3)).transpose() - p;
      const Eigen::Vector3d w = shape.V.row(shape.F(f, (c + 2) % 3)).transpose() - p;
      angle_sum[shape.F(f, c)] += std::atan2(u.cross(w).norm(), u.dot(w));
    }
  for (const double sum : angle_sum)
    if (sum > 2 * M_PI + 1e-9) return false;
  return n > 0;
}

namespace {

// What the attempts at H_C gave: the hole space, or the last reason they did
// not, and whether CGAL itself failed (rather than the result not being a
// manifold).
struct Attempts {
  std::optional<Solid> hole;
  std::string failure;
  bool cgal_failed = false;
};

// CH(C) \ C by corefinement of the exact surface `solid`, in up to three
// attempts:
// 1. Exact, C's rounded planar quads following the hull.
// 2. Every dent of C's triangulation between hull vertices flipped away.
// 3. The hull shrunk (see HULL_SHRINK in hole_space_internal.hpp).
// Each attempt either gives the hole space or a reason it did not: the
// difference is not a manifold, or CGAL failed inside the corefinement
// (the next attempt's changed operands often avoid both).
Attempts corefined_hole_space(Mesh solid, double size) {
  std::vector<Point> points;
  points.reserve(solid.number_of_vertices());
  for (const auto v : solid.vertices()) points.push_back(solid.point(v));
  Mesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  Attempts out;
  auto attempt = [&](Mesh hull_copy, Mesh solid_copy) {  // corefinement changes its operands
    Mesh hole;
    try {
      if (PMP::corefine_and_compute_difference(hull_copy, solid_copy, hole)) return out.hole = to_solid(hole), true;
      out.failure = "is not a manifold: two of its parts touch along an edge", out.cgal_failed = false;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {  // only CGAL runs in the try
      out.failure = "cannot be computed: CGAL failed: " + cgal_reason(e), out.cgal_failed = true;
    }
    return false;
  };
  for (const double tolerance : {HULL_COPLANAR * size, double(INFINITY)}) {
    follow_hull(solid, hull, tolerance);
    if (attempt(hull, solid)) return out;
  }
  shrink_hull(hull);
  attempt(hull, solid);
  return out;
}

// The same triangles, each started at its smallest vertex (orientation
// kept), in lexicographic order.
SimplexMatrix faces_in_canonical_order(const SimplexMatrix& F) {
  std::vector<std::array<Index, 3>> faces(F.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    faces[f] = {F(f, 0), F(f, 1), F(f, 2)};
    std::rotate(faces[f].begin(), std::min_element(faces[f].begin(), faces[f].end()), faces[f].end());
  }
  std::sort(faces.begin(), faces.end());
  SimplexMatrix out(F.rows(), 3);
  for (Index f = 0; f < F.rows(); ++f) out.row(f) << faces[f][0], faces[f][1], faces[f][2];
  return out;
}

}  // namespace

Solid hole_space_3d(const Operand& shape) {
  const ManifoldReport report = check_manifold(shape.F);
  if (report.boundary_facets == 0 && report.nonmanifold_facets == 0 && report.misoriented_facets == 0 &&
      report.degenerate_simplices == 0 && is_convex_surface(shape))
    return Solid{PointMatrix(0, 3), SimplexMatrix(0, 3)};
  Mesh solid = exact_mesh(shape, true);
  if (!PMP::is_outward_oriented(solid)) fail<BooleanError>(shape.name, " is inside out (its faces point inward)");
  const double size = (shape.V.colwise().maxCoeff() - shape.V.colwise().minCoeff()).norm();
  Attempts result = corefined_hole_space(std::move(solid), size);
  if (result.hole) return *result.hole;
  if (result.cgal_failed) {
    // The corefinement's face triangulation can fail on a surface and succeed
    // on the same surface given in another order of its faces (two of the
    // shared models, a CAD-like part and a genus-0 scan, do): once more in a
    // canonical order. The surface was checked above.
    const SimplexMatrix reordered = faces_in_canonical_order(shape.F);
    if (reordered != shape.F) {
      const Attempts again = corefined_hole_space(exact_mesh({shape.V, reordered, shape.name}, false), size);
      if (again.hole) return *again.hole;
    }
  }
  fail<BooleanError>("the hole space of ", shape.name, " (its convex hull minus the solid) ", result.failure);
}

bool boolean_3d(Operation operation, const Operand& a, const Operand& b, Solid& out) {
  Mesh A = exact_mesh(a, false), B = exact_mesh(b, false);
  if (!PMP::do_intersect(A, B, CGAL::parameters::do_overlap_test_of_bounded_sides(true))) {
    if (operation == Operation::Intersection) out = Solid{PointMatrix(0, 3), SimplexMatrix(0, 3)};
    return false;
  }
  Mesh result;
  bool manifold = false;
  try {
    const auto np = CGAL::parameters::throw_on_self_intersection(true);
    manifold = operation == Operation::Intersection ? PMP::corefine_and_compute_intersection(A, B, result, np)
                                                    : PMP::corefine_and_compute_difference(A, B, result, np);
  } catch (const PMP::Corefinement::Self_intersection_exception&) {
    // Name the culprit (only on this path: the full test costs as much as the operation).
    for (const Operand* s : {&a, &b}) exact_mesh(*s, true);
    fail<BooleanError>(a.name, " or ", b.name, " intersects itself where they cross");
  }
  if (!manifold)
    fail<BooleanError>(operation == Operation::Intersection ? "the intersection of " : "the difference of ", a.name,
                       " and ", b.name, " is not a manifold: two of its parts touch along an edge");
  out = to_solid(result);
  return true;
}

}  // namespace animanifold::holes
