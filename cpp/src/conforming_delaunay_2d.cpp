// Conforming Delaunay triangulation of segments in R^2 through CGAL.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_conformer_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace animanifold {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<Index, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

}  // namespace

ConformingDelaunay conforming_delaunay_2d(const PointMatrix& points, const SimplexMatrix& edges) {
  if (points.cols() != 2) fail<InputError>("conforming Delaunay in 2D needs 2D points, got ", points.cols(), "D");
  if (edges.cols() != 2) fail<InputError>("constraints in 2D must be segments, got ", edges.cols(), " corners");
  const Index n = static_cast<Index>(points.rows());
  if (n < 3) fail<InputError>("a triangulation needs at least 3 points, got ", n);
  for (Index r = 0; r < n; ++r)
    if (!std::isfinite(points(r, 0)) || !std::isfinite(points(r, 1)))
      fail<InputError>("point ", r, " has a non-finite coordinate");
  for (Index e = 0; e < edges.rows(); ++e)
    for (int c = 0; c < 2; ++c)
      if (edges(e, c) < 0 || edges(e, c) >= n)
        fail<InputError>("constraint segment ", e, " refers to point ", edges(e, c), ", outside 0..", n - 1);

  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handles(n);
  for (Index v = 0; v < n; ++v) {
    handles[v] = cdt.insert(Kernel::Point_2(points(v, 0), points(v, 1)));
    if (static_cast<Index>(cdt.number_of_vertices()) != v + 1)
      fail<InputError>("point ", v, " coincides with point ", handles[v]->info());
    handles[v]->info() = v;
  }
  translating_cgal_failures(
      "conforming " + std::to_string(edges.rows()) + " constraint segments on " + std::to_string(n) + " points", [&] {
        for (Index e = 0; e < edges.rows(); ++e) cdt.insert_constraint(handles[edges(e, 0)], handles[edges(e, 1)]);
        CGAL::make_conforming_Delaunay_2(cdt);
      });

  // Number the Steiner points after the input points.
  std::set<Cdt::Vertex_handle> inputs(handles.begin(), handles.end());
  Index next = n;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (!inputs.count(v)) v->info() = next++;
  ConformingDelaunay result;
  result.points.resize(next, 2);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    result.points.row(v->info()) << v->point().x(), v->point().y();
  result.simplices.resize(static_cast<Index>(cdt.number_of_faces()), 3);
  Index row = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f, ++row)
    for (int c = 0; c < 3; ++c) result.simplices(row, c) = f->vertex(c)->info();  // CGAL faces are counter-clockwise

  // Walk each input segment from its start to its end along constrained
  // edges: the sub-segments it was split into, in order and direction.
  std::vector<Index> corners, parents;
  for (Index e = 0; e < edges.rows(); ++e) {
    Cdt::Vertex_handle current = handles[edges(e, 0)];
    const Cdt::Vertex_handle target = handles[edges(e, 1)];
    const Eigen::Vector2d end(points(edges(e, 1), 0), points(edges(e, 1), 1));
    for (Index guard = 0; current != target; ++guard) {
      if (guard > next) fail<MeshingError>("could not follow constraint segment ", e, " after refinement");
      const Eigen::Vector2d here(current->point().x(), current->point().y());
      Cdt::Vertex_handle best;
      double best_alignment = -2;
      auto edge = cdt.incident_edges(current), done = edge;
      do {
        if (cdt.is_infinite(edge) || !cdt.is_constrained(*edge)) continue;
        const auto other = edge->first->vertex(cdt.cw(edge->second)) == current ? edge->first->vertex(cdt.ccw(edge->second))
                                                                                 : edge->first->vertex(cdt.cw(edge->second));
        const Eigen::Vector2d there(other->point().x(), other->point().y());
        const double alignment = (there - here).normalized().dot((end - here).normalized());
        if (alignment > best_alignment) best_alignment = alignment, best = other;
      } while (++edge != done);
      if (best_alignment < 1 - 1e-9) fail<MeshingError>("constraint segment ", e, " was lost in refinement");
      corners.push_back(current->info());
      corners.push_back(best->info());
      parents.push_back(e);
      current = best;
    }
  }
  result.constraints = Eigen::Map<SimplexMatrix>(corners.data(), static_cast<Index>(parents.size()), 2);
  result.constraint_parent = Eigen::Map<IndexVector>(parents.data(), static_cast<Index>(parents.size()));

  // Delaunay check with the exact in-circle predicate across every edge.
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    for (int i = 0; i < 3; ++i) {
      const auto neighbour = f->neighbor(i);
      if (cdt.is_infinite(neighbour)) continue;
      const auto apex = neighbour->vertex(neighbour->index(f));
      if (CGAL::side_of_oriented_circle(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point(),
                                        apex->point()) == CGAL::ON_POSITIVE_SIDE)
        ++result.non_delaunay_faces;
    }
  result.non_delaunay_faces /= 2;
  result.is_delaunay = result.non_delaunay_faces == 0;
  return result;
}

}  // namespace animanifold
