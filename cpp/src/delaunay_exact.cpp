// Delaunay triangulations in R^3 and R^4 through CGAL's dD Triangulation
// package (exact predicates, symbolic perturbation): see delaunay.hpp. Its
// predicates are Epick_d's, tried first in double precision
// (semi_static_kernel_d.hpp).
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "cgal_failures.hpp"
#include "semi_static_kernel_d.hpp"

#include <CGAL/Delaunay_triangulation.h>
#include <CGAL/Epick_d.h>
#include <CGAL/Triangulation_data_structure.h>
#include <CGAL/Triangulation_full_cell.h>
#include <CGAL/Triangulation_vertex.h>
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace animanifold {

namespace {

template <int D>
DelaunayTriangulation triangulate(const PointMatrix& points) {
  using Kernel = SemiStaticKernel<D>;
  using Vertex = CGAL::Triangulation_vertex<Kernel, Index>;
  using Cell = CGAL::Triangulation_full_cell<Kernel>;
  using Structure = CGAL::Triangulation_data_structure<CGAL::Dimension_tag<D>, Vertex, Cell>;
  using Triangulation = CGAL::Delaunay_triangulation<Kernel, Structure>;
  using Point = typename Kernel::Point_d;

  const Index n = static_cast<Index>(points.rows());
  std::vector<Point> input;
  input.reserve(n);
  // CGAL sorts the points along a space-filling curve before inserting them
  // (far faster than in order), which loses their indices: find them again
  // by their exact coordinates.
  struct Bits {
    size_t operator()(const std::array<double, D>& p) const {
      size_t h = 1469598103934665603ull;
      for (double x : p) {
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        h = (h ^ b) * 1099511628211ull;
      }
      return h;
    }
  };
  std::unordered_map<std::array<double, D>, Index, Bits> index_of;
  index_of.reserve(static_cast<size_t>(n));
  for (Index r = 0; r < n; ++r) {
    std::array<double, D> p;
    for (int c = 0; c < D; ++c) p[c] = points(r, c) + 0.0;  // + 0.0: -0.0 and 0.0 alike
    if (!index_of.emplace(p, r).second)
      fail<InputError>("points ", index_of.at(p), " and ", r, " coincide: a Delaunay triangulation needs distinct points");
    input.emplace_back(p.begin(), p.end());
  }
  Triangulation triangulation(D);
  triangulation.insert(input.begin(), input.end());
  if (triangulation.current_dimension() < D)
    fail<InputError>("the points span only ", triangulation.current_dimension(), " dimensions of R^", D);

  DelaunayTriangulation out;
  const auto orientation = Kernel().orientation_d_object();
  std::vector<Index> corners;
  Eigen::Matrix<double, D, D> edges;
  double factorial = 1;
  for (int i = 2; i <= D; ++i) factorial *= i;
  for (auto cell = triangulation.finite_full_cells_begin(); cell != triangulation.finite_full_cells_end(); ++cell) {
    std::array<Index, D + 1> ids;
    for (int i = 0; i <= D; ++i) {
      const Point& p = cell->vertex(i)->point();
      std::array<double, D> key;
      for (int c = 0; c < D; ++c) key[c] = p[c] + 0.0;
      ids[i] = index_of.at(key);
    }
    double product = factorial;
    for (int r = 0; r < D; ++r) {
      edges.row(r) = points.row(ids[r + 1]) - points.row(ids[0]);
      product *= edges.row(r).norm();
    }
    const double volume = edges.determinant();
    // The same flatness rule as Qhull's path (delaunay.cpp): the cell is a
    // proper one for CGAL's exact predicates, but a volume this small next
    // to Hadamard's bound is roundoff in every later computation. Its
    // orientation is the exact predicate's, not the rounded determinant's.
    bool negative = volume < 0;
    if (std::abs(volume) <= 1e-12 * product) {
      out.slivers.push_back(static_cast<Index>(corners.size() / (D + 1)));
      std::array<Point, D + 1> corner;
      for (int i = 0; i <= D; ++i) corner[i] = cell->vertex(i)->point();
      // Points as in `points`, in the order of ids.
      negative = orientation(corner.begin(), corner.end()) == CGAL::NEGATIVE;
    }
    if (negative) std::swap(ids[0], ids[1]);
    corners.insert(corners.end(), ids.begin(), ids.end());
  }
  out.simplices = Eigen::Map<SimplexMatrix>(corners.data(), static_cast<Index>(corners.size() / (D + 1)), D + 1);
  out.flat.resize(0, D + 1);
  return out;
}

}  // namespace

DelaunayTriangulation delaunay_exact(const PointMatrix& points) {
  const int d = static_cast<int>(points.cols());
  const Index n = static_cast<Index>(points.rows());
  if (d != 3 && d != 4) fail<InputError>("exact Delaunay triangulation is built for R^3 and R^4, got R^", d);
  if (n < d + 1) fail<InputError>("Delaunay triangulation in R^", d, " needs at least ", d + 1, " points, got ", n);
  for (Index r = 0; r < n; ++r)
    for (int c = 0; c < d; ++c)
      if (!std::isfinite(points(r, c))) fail<InputError>("point ", r, " has a non-finite coordinate");
  return translating_cgal_failures("triangulating " + std::to_string(n) + " points in R^" + std::to_string(d),
                                   [&] { return d == 3 ? triangulate<3>(points) : triangulate<4>(points); });
}

}  // namespace animanifold
