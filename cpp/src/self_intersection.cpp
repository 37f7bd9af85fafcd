#include "animanifold/self_intersection.hpp"

#include "animanifold/errors.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>
#include <algorithm>
#include <iterator>

namespace animanifold {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

std::vector<std::pair<Index, Index>> triangle_pairs(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs) {
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vertex(V.rows());
  for (Index v = 0; v < V.rows(); ++v) vertex[v] = mesh.add_vertex(Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)));
  std::vector<Index> face_id;
  for (Index f = 0; f < F.rows(); ++f) {
    if (mesh.add_face(vertex[F(f, 0)], vertex[F(f, 1)], vertex[F(f, 2)]) == Mesh::null_face())
      fail<InputError>("face ", f, " cannot join the surface (the shape is not a manifold there)");
    face_id.push_back(f);
  }
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh.faces(), mesh, std::back_inserter(pairs));
  std::vector<std::pair<Index, Index>> out;
  for (const auto& [a, b] : pairs) {
    const Index fa = face_id[static_cast<std::size_t>(a)], fb = face_id[static_cast<std::size_t>(b)];
    out.emplace_back(std::min(fa, fb), std::max(fa, fb));
  }
  std::sort(out.begin(), out.end());
  if (max_pairs && out.size() > max_pairs) out.resize(max_pairs);
  return out;
}

std::vector<std::pair<Index, Index>> segment_pairs(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs) {
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
      out.emplace_back(a, b);
      if (max_pairs && out.size() >= max_pairs) return out;
    }
  return out;
}

}  // namespace

std::vector<std::pair<Index, Index>> self_intersections(const PointMatrix& V, const SimplexMatrix& F, std::size_t max_pairs) {
  if (V.cols() == 3 && F.cols() == 3) return triangle_pairs(V, F, max_pairs);
  if (V.cols() == 2 && F.cols() == 2) return segment_pairs(V, F, max_pairs);
  fail<InputError>("self-intersection is checked for triangles in R^3 and segments in R^2, got ", F.cols(),
                   "-corner faces in R^", V.cols());
}

}  // namespace animanifold
