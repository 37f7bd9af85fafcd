// Hole spaces and solid Booleans of closed polygons in R^2: CGAL's
// convex_hull_2 and Boolean set operations on Polygon_set_2 with an
// exact-constructions kernel (Epeck), rounded to doubles at the end.
#include "animanifold/errors.hpp"
#include "hole_space_internal.hpp"

#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/convex_hull_2.h>

#include <cmath>
#include <iterator>
#include <map>
#include <vector>

namespace animanifold::holes {

namespace {

using K = ExactKernel;
using Point = K::Point_2;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using PolygonSet = CGAL::Polygon_set_2<K>;

// The loops of a set of oriented edges (vertex ids in order), or a
// BooleanError where a vertex has not as many edges in as out. Where loops
// touch at a vertex (k > 1 edges in and out: a frame that pinches), each
// arriving edge goes on along the leaving edge met first turning clockwise
// from the way back, so that every loop keeps its region on its left and
// loops never cross there.
std::vector<std::vector<Index>> loops_of(const Operand& s) {
  const Index n = static_cast<Index>(s.V.rows()), m = static_cast<Index>(s.F.rows());
  std::vector<std::vector<Index>> leaving(n);
  std::vector<Index> arriving(n, 0);
  for (Index f = 0; f < m; ++f) {
    const Index a = s.F(f, 0), b = s.F(f, 1);
    if (a == b) fail<BooleanError>(s.name, "'s edge ", f, " starts and ends at vertex ", a);
    leaving[a].push_back(f), ++arriving[b];
  }
  for (Index v = 0; v < n; ++v)
    if (static_cast<Index>(leaving[v].size()) != arriving[v])
      fail<BooleanError>(s.name, " is not a set of closed loops at vertex ", v, " (", leaving[v].size(),
                         " edges leave, ", arriving[v], " arrive)");
  std::vector<Index> next(m, -1);
  std::vector<bool> taken(m, false);
  for (Index f = 0; f < m; ++f) {
    const Index u = s.F(f, 0), v = s.F(f, 1);
    const std::vector<Index>& out = leaving[v];
    if (out.size() == 1) {
      next[f] = out[0];
      continue;
    }
    const double back = std::atan2(s.V(u, 1) - s.V(v, 1), s.V(u, 0) - s.V(v, 0));
    double best = INFINITY;
    for (const Index g : out) {
      const Index w = s.F(g, 1);
      double clockwise = back - std::atan2(s.V(w, 1) - s.V(v, 1), s.V(w, 0) - s.V(v, 0));
      while (clockwise <= 0) clockwise += 2 * M_PI;
      while (clockwise > 2 * M_PI) clockwise -= 2 * M_PI;
      if (clockwise < best) best = clockwise, next[f] = g;
    }
  }
  for (Index f = 0; f < m; ++f) {
    if (taken[next[f]])
      fail<BooleanError>(s.name, "'s loops cross at vertex ", s.F(f, 1), " (they may only touch there)");
    taken[next[f]] = true;
  }
  std::vector<std::vector<Index>> loops;
  std::vector<bool> seen(m, false);
  for (Index f = 0; f < m; ++f) {
    if (seen[f]) continue;
    loops.emplace_back();
    for (Index e = f; !seen[e]; e = next[e]) seen[e] = true, loops.back().push_back(s.F(e, 0));
  }
  return loops;
}

// Splits a closed sequence of points where it comes back to a point it has
// passed (loops that touch themselves there: a frame that pinches) into
// loops that do not, skipping repeated consecutive points (edges of zero
// length, as slicing near a vertex gives).
std::vector<std::vector<Point>> simple_pieces(const std::vector<Point>& points) {
  std::vector<std::vector<Point>> pieces;
  std::vector<Point> stack;
  std::map<Point, std::size_t, K::Less_xy_2> position;  // of each point on the stack
  for (const Point& p : points) {
    if (!stack.empty() && stack.back() == p) continue;
    const auto seen = position.find(p);
    if (seen == position.end()) {
      position.emplace(p, stack.size());
      stack.push_back(p);
      continue;
    }
    // p closes the piece stack[seen .. end): cut it off, keep p on the stack.
    pieces.emplace_back(stack.begin() + static_cast<std::ptrdiff_t>(seen->second), stack.end());
    for (std::size_t i = seen->second + 1; i < stack.size(); ++i) position.erase(stack[i]);
    stack.resize(seen->second + 1);
  }
  if (!stack.empty()) pieces.push_back(std::move(stack));
  return pieces;
}

// The region bounded by the loops: the symmetric difference of their
// interiors, which is what oriented, properly nested loops bound (an island
// in a hole in a disc included). Loops without area are dropped.
PolygonSet region_of(const Operand& s, double* signed_area = nullptr) {
  PolygonSet region;
  K::FT area = 0;
  for (const std::vector<Index>& loop : loops_of(s)) {
    std::vector<Point> points;
    points.reserve(loop.size() + 1);
    for (const Index v : loop) points.emplace_back(s.V(v, 0), s.V(v, 1));
    points.push_back(points.front());  // closes the loop, so its end splits off like any other piece
    for (std::vector<Point>& piece : simple_pieces(points)) {
      if (piece.size() < 3) continue;
      Polygon polygon(piece.begin(), piece.end());
      const K::FT loop_area = polygon.area();
      if (loop_area == 0) continue;
      if (!polygon.is_simple())
        fail<BooleanError>(s.name, "'s loop through vertex ", loop.front(), " crosses itself");
      area += loop_area;
      if (loop_area < 0) polygon.reverse_orientation();
      region.symmetric_difference(polygon);
    }
  }
  if (signed_area) *signed_area = rounded(area);
  return region;
}

Solid to_solid(const PolygonSet& set) {
  std::vector<PolygonWithHoles> parts;
  set.polygons_with_holes(std::back_inserter(parts));
  std::vector<const Polygon*> loops;
  Index points = 0;
  for (const PolygonWithHoles& part : parts) {
    loops.push_back(&part.outer_boundary());
    for (auto h = part.holes_begin(); h != part.holes_end(); ++h) loops.push_back(&*h);
  }
  for (const Polygon* loop : loops) points += static_cast<Index>(loop->size());
  Solid out;
  out.vertices.resize(points, 2);
  out.faces.resize(points, 2);
  Index first = 0;
  for (const Polygon* loop : loops) {
    const Index size = static_cast<Index>(loop->size());
    for (Index i = 0; i < size; ++i) {
      const Point& p = (*loop)[i];
      out.vertices.row(first + i) << rounded(p.x()), rounded(p.y());
      out.faces.row(first + i) << first + i, first + (i + 1) % size;
    }
    first += size;
  }
  return out;
}

}  // namespace

Solid hole_space_2d(const Operand& shape) {
  double area = 0;
  const PolygonSet region = region_of(shape, &area);
  if (area <= 0) fail<BooleanError>(shape.name, " is inside out (its loops run clockwise) or encloses no area");
  std::vector<Point> points, hull;
  for (Index f = 0; f < shape.F.rows(); ++f) points.emplace_back(shape.V(shape.F(f, 0), 0), shape.V(shape.F(f, 0), 1));
  CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(hull));
  PolygonSet hole(Polygon(hull.begin(), hull.end()));
  hole.difference(region);
  return to_solid(hole);
}

bool boolean_2d(Operation operation, const Operand& a, const Operand& b, Solid& out) {
  PolygonSet A = region_of(a);
  const PolygonSet B = region_of(b);
  if (!A.do_intersect(B)) {
    if (operation == Operation::Intersection) out = Solid{PointMatrix(0, 2), SimplexMatrix(0, 2)};
    return false;
  }
  if (operation == Operation::Intersection) A.intersection(B);
  else A.difference(B);
  out = to_solid(A);
  return true;
}

}  // namespace animanifold::holes
