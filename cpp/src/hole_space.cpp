#include "animanifold/hole_space.hpp"

#include "animanifold/errors.hpp"
#include "hole_space_internal.hpp"
#include "isolated_boolean.hpp"
#include "signed_distance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace animanifold {

namespace {

// Shapes, indices and finiteness (InputError); what CGAL needs beyond that
// is checked where the exact meshes are built.
void check_arrays(const holes::Operand& s) {
  const auto d = s.V.cols();
  if (d != 2 && d != 3) fail<InputError>(s.name, " must have 2D or 3D points, got ", d, " columns");
  if (s.F.rows() > 0 && s.F.cols() != d)
    fail<InputError>(s.name, " must have ", d == 3 ? "triangles (3 columns)" : "edges (2 columns)", " for ", d,
                     "D points, got ", s.F.cols(), " columns");
  for (Index f = 0; f < s.F.rows(); ++f)
    for (Index c = 0; c < s.F.cols(); ++c)
      if (s.F(f, c) < 0 || s.F(f, c) >= s.V.rows())
        fail<InputError>(s.name, "'s face ", f, " refers to vertex ", s.F(f, c), ", outside 0..", s.V.rows() - 1);
  for (Index v = 0; v < s.V.rows(); ++v)
    for (Index c = 0; c < d; ++c)
      if (!std::isfinite(s.V(v, c))) fail<InputError>(s.name, "'s vertex ", v, " is not finite");
}

void check_pair(const holes::Operand& a, const holes::Operand& b) {
  check_arrays(a);
  check_arrays(b);
  if (a.V.cols() != b.V.cols())
    fail<InputError>(a.name, " is ", a.V.cols(), "D but ", b.name, " is ", b.V.cols(), "D");
}

// Do the bounding boxes of the used vertices overlap with positive measure?
// (Boxes that only touch cannot hold a common volume.)
bool boxes_overlap(const holes::Operand& a, const holes::Operand& b) {
  const auto d = a.V.cols();
  Eigen::RowVectorXd lo_a = Eigen::RowVectorXd::Constant(d, INFINITY), hi_a = -lo_a, lo_b = lo_a, hi_b = hi_a;
  for (Index f = 0; f < a.F.rows(); ++f)
    for (Index c = 0; c < d; ++c) lo_a = lo_a.cwiseMin(a.V.row(a.F(f, c))), hi_a = hi_a.cwiseMax(a.V.row(a.F(f, c)));
  for (Index f = 0; f < b.F.rows(); ++f)
    for (Index c = 0; c < d; ++c) lo_b = lo_b.cwiseMin(b.V.row(b.F(f, c))), hi_b = hi_b.cwiseMax(b.V.row(b.F(f, c)));
  for (Index c = 0; c < d; ++c)
    if (!(lo_a(c) < hi_b(c) && lo_b(c) < hi_a(c))) return false;
  return true;
}

// CGAL's Boolean operations number their output in an order that depends on
// memory addresses: the same operands can come back numbered differently
// from one call to the next. Sorting vertices (lexicographically) and faces
// (each started at its smallest vertex, orientation kept; then the rows)
// makes equal results equal arrays.
Solid canonical(Solid s) {
  const Index n = static_cast<Index>(s.vertices.rows()), d = static_cast<Index>(s.vertices.cols());
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
    for (Index c = 0; c < d; ++c)
      if (s.vertices(a, c) != s.vertices(b, c)) return s.vertices(a, c) < s.vertices(b, c);
    return false;
  });
  std::vector<Index> rank(n);
  PointMatrix vertices(n, d);
  for (Index i = 0; i < n; ++i) rank[order[i]] = i, vertices.row(i) = s.vertices.row(order[i]);
  const Index k = static_cast<Index>(s.faces.cols());
  std::vector<std::vector<Index>> faces(s.faces.rows(), std::vector<Index>(k));
  for (Index f = 0; f < s.faces.rows(); ++f) {
    for (Index c = 0; c < k; ++c) faces[f][c] = rank[s.faces(f, c)];
    if (k == 3) std::rotate(faces[f].begin(), std::min_element(faces[f].begin(), faces[f].end()), faces[f].end());
  }
  std::sort(faces.begin(), faces.end());
  s.vertices = std::move(vertices);
  for (Index f = 0; f < s.faces.rows(); ++f)
    for (Index c = 0; c < k; ++c) s.faces(f, c) = faces[f][c];
  return s;
}

Solid empty_like(const PointMatrix& V) {
  Solid s;
  s.vertices.resize(0, V.cols());
  s.faces.resize(0, V.cols());
  return s;
}

// Runs one of CGAL's Boolean operations (a ∩ b, a \ b) in a child process (isolated_boolean.hpp):
// what it made, and whether that differs from a.
holes::BooleanOutcome isolated_boolean_operation(holes::Operation operation, const holes::Operand& a,
                                                 const holes::Operand& b, const std::string& doing,
                                                 const Interrupter& interrupter) {
  const auto work = [&] {
    holes::BooleanOutcome outcome;
    outcome.changed = translating_cgal_failures<BooleanError>(doing, [&] {
      return a.V.cols() == 3 ? holes::boolean_3d(operation, a, b, outcome.solid)
                             : holes::boolean_2d(operation, a, b, outcome.solid);
    });
    return outcome;
  };
  return holes::isolated_boolean(doing, work, holes::boolean_time_limit(a.F.rows() + b.F.rows()), interrupter);
}

}  // namespace

Solid hole_space(const PointMatrix& V, const SimplexMatrix& F, const Interrupter& interrupter) {
  const holes::Operand shape{V, F, "the shape"};
  check_arrays(shape);
  if (F.rows() == 0) fail<InputError>("the shape has no faces");
  const std::string doing = "computing the hole space of the shape";
  const auto work = [&] {
    return holes::BooleanOutcome{translating_cgal_failures<BooleanError>(doing, [&] {
      return V.cols() == 3 ? holes::hole_space_3d(shape) : holes::hole_space_2d(shape);
    })};
  };
  return canonical(holes::isolated_boolean(doing, work, holes::boolean_time_limit(F.rows()), interrupter).solid);
}

Solid intersect_solids(const PointMatrix& VA, const SimplexMatrix& FA, const PointMatrix& VB,
                       const SimplexMatrix& FB, const Interrupter& interrupter) {
  const holes::Operand a{VA, FA, "the first solid"}, b{VB, FB, "the second solid"};
  check_pair(a, b);
  Solid out = empty_like(VA);
  if (FA.rows() == 0 || FB.rows() == 0 || !boxes_overlap(a, b)) return out;
  holes::BooleanOutcome outcome =
      isolated_boolean_operation(holes::Operation::Intersection, a, b, "intersecting two solids", interrupter);
  return outcome.changed ? canonical(std::move(outcome.solid)) : out;
}

Subtraction subtract_solid(const PointMatrix& V, const SimplexMatrix& F, const PointMatrix& VH,
                           const SimplexMatrix& FH, const Interrupter& interrupter) {
  const holes::Operand frame{V, F, "the frame"}, hole{VH, FH, "the subtracted solid"};
  check_pair(frame, hole);
  Subtraction result;
  bool changed = false;
  if (F.rows() > 0 && FH.rows() > 0 && boxes_overlap(frame, hole)) {
    holes::BooleanOutcome outcome = isolated_boolean_operation(holes::Operation::Difference, frame, hole,
                                                               "subtracting a solid from the frame", interrupter);
    changed = outcome.changed;
    result.solid = std::move(outcome.solid);
  }
  result.solid = changed ? canonical(std::move(result.solid)) : Solid{V, F};
  result.unchanged = !changed;
  return result;
}

bool intersects_itself(const PointMatrix& V, const SimplexMatrix& F) {
  const holes::Operand shape{V, F, "the mesh"};
  check_arrays(shape);
  if (V.cols() != 3) fail<InputError>("the mesh must have 3D points to test it for self-intersection");
  return F.rows() > 0 && translating_cgal_failures<BooleanError>("testing the mesh for self-intersection",
                                                         [&] { return holes::intersects_itself_3d(shape); });
}

Eigen::Array<bool, Eigen::Dynamic, 1> points_inside_solid(const PointMatrix& V, const SimplexMatrix& F,
                                                          const PointMatrix& points) {
  check_arrays({V, F, "the solid"});
  if (V.cols() != 3) fail<InputError>("the solid must have 3D points to test points inside it");
  if (points.cols() != 3) fail<InputError>("the points must be 3D, got ", points.cols(), " columns");
  if (F.rows() == 0) return Eigen::Array<bool, Eigen::Dynamic, 1>::Zero(points.rows());
  return SignedDistance(V, F).inside(points);
}

double solid_measure(const PointMatrix& V, const SimplexMatrix& F) {
  check_arrays({V, F, "the solid"});
  if (F.rows() == 0) return 0.0;
  // Cones from a point of the solid (not the origin): no cancellation of
  // large terms when the solid is far from the origin.
  const Eigen::RowVectorXd o = V.row(F(0, 0));
  double sum = 0.0;
  if (V.cols() == 3) {
    for (Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)) - o, b = V.row(F(f, 1)) - o, c = V.row(F(f, 2)) - o;
      sum += a.dot(b.cross(c));
    }
    return sum / 6.0;
  }
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVectorXd a = V.row(F(f, 0)) - o, b = V.row(F(f, 1)) - o;
    sum += a(0) * b(1) - b(0) * a(1);
  }
  return sum / 2.0;
}

}  // namespace animanifold
