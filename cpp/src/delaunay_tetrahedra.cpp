// delaunay_tetrahedra (delaunay.hpp): CGAL's 3D Delaunay triangulation.
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <vector>

namespace animanifold {

SimplexMatrix delaunay_tetrahedra(const PointMatrix& points) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Vertex = CGAL::Triangulation_vertex_base_with_info_3<Index, Kernel>;
  using Structure = CGAL::Triangulation_data_structure_3<Vertex>;
  using Triangulation = CGAL::Delaunay_triangulation_3<Kernel, Structure>;
  if (points.cols() != 3) fail<InputError>("delaunay_tetrahedra takes points in R^3, got R^", points.cols());
  std::vector<std::pair<Kernel::Point_3, Index>> input;
  input.reserve(points.rows());
  for (Index r = 0; r < points.rows(); ++r) {
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(points(r, c))) fail<InputError>("point ", r, " has a non-finite coordinate");
    input.emplace_back(Kernel::Point_3(points(r, 0), points(r, 1), points(r, 2)), r);
  }
  const Triangulation dt = translating_cgal_failures(
      "triangulating " + std::to_string(points.rows()) + " points in R^3",
      [&] { return Triangulation(input.begin(), input.end()); });
  if (dt.dimension() < 3) fail<InputError>("the points span only ", dt.dimension(), " dimensions of R^3");
  if (static_cast<Index>(dt.number_of_vertices()) != points.rows())
    fail<InputError>("coinciding points: a Delaunay triangulation needs distinct points");
  SimplexMatrix cells(static_cast<Index>(dt.number_of_finite_cells()), 4);
  Index row = 0;
  for (auto cell = dt.finite_cells_begin(); cell != dt.finite_cells_end(); ++cell, ++row)
    for (int k = 0; k < 4; ++k) cells(row, k) = cell->vertex(k)->info();  // CGAL's cells are positively oriented
  return cells;
}

}  // namespace animanifold
