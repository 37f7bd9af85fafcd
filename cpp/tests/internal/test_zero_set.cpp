// Marching simplices (zero_set.hpp): every sign pattern of one 4-simplex,
// orientation by the field's gradient, zeros counted positive, and the
// zero set of random fields over a 4D Delaunay triangulation as a manifold
// whose boundary is the zero set of the triangulation's boundary.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "zero_set.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace animanifold {
namespace {

using Row = Eigen::Matrix<double, 1, Eigen::Dynamic>;

PointMatrix cut_points(const ZeroSetBuilder& zero, const PointMatrix& X) {
  PointMatrix out(static_cast<Index>(zero.cuts().size()), X.cols());
  for (size_t c = 0; c < zero.cuts().size(); ++c) {
    const ZeroCut& p = zero.cuts()[c];
    out.row(static_cast<Index>(c)) = (1 - p.s) * X.row(p.a) + p.s * X.row(p.b);
  }
  return out;
}

SimplexMatrix pieces_of(const ZeroSetBuilder& zero) {
  return Eigen::Map<const SimplexMatrix>(zero.pieces().data(), static_cast<Index>(zero.piece_count()),
                                         zero.corners() - 1);
}

// The zero set of `phi` over 4-simplices (positively oriented, as delaunay_exact gives them).
ZeroSetBuilder zero_set_of(const SimplexMatrix& simplices, const Eigen::VectorXd& phi) {
  ZeroSetBuilder zero(5);
  for (Index s = 0; s < simplices.rows(); ++s) {
    double value[5];
    for (int c = 0; c < 5; ++c) value[c] = phi(simplices(s, c));
    zero.add(simplices.row(s).data(), value, s);
  }
  return zero;
}

// The standard 4-simplex (0, e1, e2, e3, e4): positively oriented.
PointMatrix standard_simplex() {
  PointMatrix X = PointMatrix::Zero(5, 4);
  for (int k = 0; k < 4; ++k) X(k + 1, k) = 1.0;
  return X;
}

// Coordinates of `x` in the tet `corners` (4 points in R^4): (λ1, λ2, λ3)
// with x = c0 + Σ λi (ci - c0), and the distance of x from the tet's plane.
std::pair<Eigen::Vector3d, double> tet_coordinates(const PointMatrix& C, const Eigen::Vector4d& x) {
  Eigen::Matrix<double, 4, 3> M;
  for (int i = 0; i < 3; ++i) M.col(i) = (C.row(i + 1) - C.row(0)).transpose();
  const Eigen::Vector4d rhs = x - C.row(0).transpose();
  const Eigen::Vector3d lambda = M.colPivHouseholderQr().solve(rhs);
  return {lambda, (M * lambda - rhs).norm()};
}

TEST(ZeroSet, EverySignPatternOfOneSimplexTilesItsCrossSectionWithPositivePieces) {
  const PointMatrix X = standard_simplex();
  const Index ids[5] = {0, 1, 2, 3, 4};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> magnitude(0.3, 2.0), unit(0.0, 1.0);
  int patterns = 0, with_pieces = 0;
  for (int code = 0; code < 243; ++code) {  // each vertex -, 0 or +
    double value[5];
    std::vector<int> negative, positive;
    for (int v = 0, c = code; v < 5; ++v, c /= 3) {
      const int sign = c % 3 - 1;
      value[v] = sign * magnitude(rng);
      (value[v] < 0 ? negative : positive).push_back(v);  // zero counts as positive
    }
    ++patterns;
    ZeroSetBuilder zero(5);
    zero.add(ids, value, 0);
    const PointMatrix C = cut_points(zero, X);
    const SimplexMatrix pieces = pieces_of(zero);
    // the field is affine here: phi(x) = value[0] + g . x
    const Eigen::Vector4d g(value[1] - value[0], value[2] - value[0], value[3] - value[0], value[4] - value[0]);
    for (Index c = 0; c < C.rows(); ++c) EXPECT_NEAR(value[0] + g.dot(C.row(c).transpose()), 0.0, 1e-12) << code;
    if (negative.empty() || positive.empty()) {
      EXPECT_EQ(pieces.rows(), 0) << code;
      continue;
    }
    // A piece per staircase path (3 for a 2|3 split, 1 otherwise), fewer where zeros collapse corners.
    const Index full = negative.size() == 1 || positive.size() == 1 ? 1 : 3;
    EXPECT_LE(pieces.rows(), full) << code;
    const bool zeros = std::any_of(value, value + 5, [](double v) { return v == 0.0; });
    if (!zeros) EXPECT_EQ(pieces.rows(), full) << code;
    // The cross-section is 3-dimensional exactly when its points span 3 dimensions.
    PointMatrix spread(C.rows(), 4);
    for (Index c = 0; c < C.rows(); ++c) spread.row(c) = C.row(c) - C.row(0);
    const bool solid = Eigen::FullPivLU<Eigen::MatrixXd>(spread).rank() == 3;
    EXPECT_EQ(pieces.rows() > 0, solid) << code;
    if (!solid) continue;
    ++with_pieces;
    // Oriented so that the field grows on the positive side: det[c1-c0, c2-c0, c3-c0, g] > 0.
    for (Index p = 0; p < pieces.rows(); ++p) {
      Eigen::Matrix4d M;
      for (int i = 0; i < 3; ++i) M.col(i) = (C.row(pieces(p, i + 1)) - C.row(pieces(p, 0))).transpose();
      M.col(3) = g;
      EXPECT_GT(M.determinant(), 1e-12) << code << " piece " << p;
    }
    // Random points of the zero set in the simplex (on segments from N's hull to P's) lie in
    // exactly one piece: the pieces cover the cross-section and do not overlap.
    for (int sample = 0; sample < 200; ++sample) {
      Eigen::Vector4d a = Eigen::Vector4d::Zero(), b = Eigen::Vector4d::Zero();
      double va = 0, vb = 0, wa = 0, wb = 0;
      for (const int v : negative) {
        const double w = unit(rng) + 1e-3;
        a += w * X.row(v).transpose(), va += w * value[v], wa += w;
      }
      for (const int v : positive) {
        const double w = unit(rng) + 1e-3;
        b += w * X.row(v).transpose(), vb += w * value[v], wb += w;
      }
      a /= wa, va /= wa, b /= wb, vb /= wb;
      if (!(vb > 1e-3)) continue;  // b on the zero set itself (all of P's values zero)
      const Eigen::Vector4d x = a + (va / (va - vb)) * (b - a);
      int inside = 0;
      for (Index p = 0; p < pieces.rows(); ++p) {
        PointMatrix corners(4, 4);
        for (int i = 0; i < 4; ++i) corners.row(i) = C.row(pieces(p, i));
        const auto [lambda, off_plane] = tet_coordinates(corners, x);
        EXPECT_LT(off_plane, 1e-9);
        if (lambda.minCoeff() > -1e-9 && lambda.sum() < 1 + 1e-9) ++inside;
      }
      EXPECT_EQ(inside, 1) << code << " sample " << sample;
    }
  }
  EXPECT_EQ(patterns, 243);
  EXPECT_GT(with_pieces, 100);
}

TEST(ZeroSet, ACutFromAZeroVertexIsTheVertexItself) {
  const PointMatrix X = standard_simplex();
  const Index ids[5] = {10, 11, 12, 13, 14};
  const double value[5] = {-1.0, 0.0, 2.0, 0.5, 1.5};
  ZeroSetBuilder zero(5);
  zero.add(ids, value, 3);
  int at_vertex = 0;
  for (const ZeroCut& c : zero.cuts())
    if (c.a == c.b) {
      EXPECT_EQ(c.a, 11);
      EXPECT_EQ(c.s, 0.0);
      ++at_vertex;
    }
  EXPECT_EQ(at_vertex, 1);  // the edge 10-11 (the only negative-zero edge) cuts at vertex 11
  ASSERT_EQ(zero.piece_count(), 1u);
  EXPECT_EQ(zero.sources()[0], 3);
}

// Pieces as sets of cut edges, so two builders' pieces compare.
using EdgeSet = std::set<std::pair<Index, Index>>;
std::multiset<EdgeSet> as_edge_sets(const ZeroSetBuilder& zero, const SimplexMatrix& pieces) {
  std::multiset<EdgeSet> out;
  for (Index p = 0; p < pieces.rows(); ++p) {
    EdgeSet s;
    for (Index c = 0; c < pieces.cols(); ++c) {
      const ZeroCut& cut = zero.cuts()[pieces(p, c)];
      s.insert({cut.a, cut.b});
    }
    out.insert(s);
  }
  return out;
}

// Random points in [0,1]^4 and their Delaunay triangulation, a random field with some exact zeros:
// the zero set is an oriented 3-manifold (every triangle in at most two pieces, oppositely) whose
// boundary is exactly the zero set of the triangulation's boundary tets.
TEST(ZeroSet, RandomFieldsGiveAClosedManifoldUpToTheDomainsBoundary) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    PointMatrix X(120, 4);
    for (Index i = 0; i < X.rows(); ++i)
      for (int k = 0; k < 4; ++k) X(i, k) = unit(rng);
    const DelaunayTriangulation dt = delaunay_exact(X);
    ASSERT_GT(dt.simplices.rows(), 100);
    Eigen::VectorXd phi(X.rows());
    for (Index i = 0; i < X.rows(); ++i) {
      phi(i) = (X.row(i) - Row::Constant(1, 4, 0.5)).norm() - 0.3 - 0.1 * std::sin(7.0 * X(i, 3));
      if (i % 9 == 0) phi(i) = 0.0;  // exact zeros: counted positive
    }
    const ZeroSetBuilder zero = zero_set_of(dt.simplices, phi);
    const SimplexMatrix pieces = pieces_of(zero);
    ASSERT_GT(pieces.rows(), 50) << seed;
    const ManifoldReport report = check_manifold(pieces);
    EXPECT_TRUE(report.is_oriented_manifold()) << seed << ": " << report.nonmanifold_facets << " non-manifold, "
                                               << report.misoriented_facets << " misoriented";
    // The boundary of the zero set is the zero set of the boundary.
    const SimplexMatrix hull = boundary_facets(dt.simplices);
    ZeroSetBuilder on_hull(4);
    for (Index f = 0; f < hull.rows(); ++f) {
      double value[4];
      for (int c = 0; c < 4; ++c) value[c] = phi(hull(f, c));
      on_hull.add(hull.row(f).data(), value, f);
    }
    const SimplexMatrix edge_of_zero = boundary_facets(pieces);
    std::multiset<EdgeSet> boundary;
    for (Index f = 0; f < edge_of_zero.rows(); ++f) {
      EdgeSet s;
      for (Index c = 0; c < 3; ++c) {
        const ZeroCut& cut = zero.cuts()[edge_of_zero(f, c)];
        s.insert({cut.a, cut.b});
      }
      boundary.insert(s);
    }
    EXPECT_EQ(boundary, as_edge_sets(on_hull, pieces_of(on_hull))) << seed;
  }
}

// A complex extracted in two parts, each by a builder of its own, then one
// appended to the other, is the complex extracted whole: the same cut points,
// each once (those on the seam between the parts welded), and the same
// pieces over them.
TEST(ZeroSet, TwoPartsExtractedApartThenAppendedAreTheWhole) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PointMatrix X(150, 4);
  for (Index i = 0; i < X.rows(); ++i)
    for (int k = 0; k < 4; ++k) X(i, k) = unit(rng);
  const DelaunayTriangulation dt = delaunay_exact(X);
  Eigen::VectorXd phi(X.rows());
  for (Index i = 0; i < X.rows(); ++i) phi(i) = (X.row(i) - Row::Constant(1, 4, 0.5)).norm() - 0.35;
  const ZeroSetBuilder whole = zero_set_of(dt.simplices, phi);
  // The parts: simplices whose centroid lies left or right of x = 0.5.
  ZeroSetBuilder left(5), right(5);
  Index on_seam = 0;
  for (Index s = 0; s < dt.simplices.rows(); ++s) {
    double value[5], x = 0;
    for (int c = 0; c < 5; ++c) value[c] = phi(dt.simplices(s, c)), x += X(dt.simplices(s, c), 0) / 5;
    (x < 0.5 ? left : right).add(dt.simplices.row(s).data(), value, s);
  }
  const size_t left_cuts = left.cuts().size(), right_cuts = right.cuts().size();
  left.append(right);
  on_seam = static_cast<Index>(left_cuts + right_cuts - left.cuts().size());
  ASSERT_GT(whole.piece_count(), 50u);
  EXPECT_GT(on_seam, 0) << "the parts share no cut: the test splits nothing";
  EXPECT_EQ(left.cuts().size(), whole.cuts().size());
  EXPECT_EQ(left.piece_count(), whole.piece_count());
  EXPECT_EQ(as_edge_sets(left, pieces_of(left)), as_edge_sets(whole, pieces_of(whole)));
  std::set<std::tuple<Index, Index, double>> cuts_whole, cuts_parts;
  for (const ZeroCut& c : whole.cuts()) cuts_whole.insert({c.a, c.b, c.s});
  for (const ZeroCut& c : left.cuts()) cuts_parts.insert({c.a, c.b, c.s});
  EXPECT_EQ(cuts_parts, cuts_whole);
  EXPECT_TRUE(check_manifold(pieces_of(left)).is_oriented_manifold());
  EXPECT_THROW(left.append(ZeroSetBuilder(4)), InputError);
}

// An end facet: points at t = 0 and t = 1 with the field exactly zero on a sphere's points at t = 0.
// Those points are cut points of the zero set (at their own vertex), and the zero set's boundary
// on t = 0 is a closed surface through them.
TEST(ZeroSet, ZerosOnAnEndFacetBecomeTheBoundaryOfTheZeroSet) {
  std::vector<Eigen::Vector4d> points;
  const double r = 0.5;
  for (int t = 0; t <= 1; ++t) {
    for (int axis = 0; axis < 3; ++axis)
      for (const double sign : {-1.0, 1.0}) {
        Eigen::Vector4d p = Eigen::Vector4d::Zero();
        p(axis) = sign * r;
        p(3) = t;
        points.push_back(p);
      }
    for (const double x : {-1.0, 1.0})
      for (const double y : {-1.0, 1.0})
        for (const double z : {-1.0, 1.0}) points.emplace_back(x, y, z, t);
    points.emplace_back(0.01, 0.02, 0.03, t);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> inner(-0.9, 0.9), middle(0.2, 0.8);
  for (int i = 0; i < 30; ++i) points.emplace_back(inner(rng), inner(rng), inner(rng), middle(rng));
  PointMatrix X(static_cast<Index>(points.size()), 4);
  for (size_t i = 0; i < points.size(); ++i) X.row(static_cast<Index>(i)) = points[i].transpose();
  const DelaunayTriangulation dt = delaunay_exact(X);
  Eigen::VectorXd phi(X.rows());
  for (Index i = 0; i < X.rows(); ++i) phi(i) = X.row(i).head(3).norm() - r * (1 + 0.3 * X(i, 3));
  for (Index i = 0; i < 6; ++i) ASSERT_EQ(phi(i), 0.0);  // the axis points at t = 0, exactly
  const ZeroSetBuilder zero = zero_set_of(dt.simplices, phi);
  const SimplexMatrix pieces = pieces_of(zero);
  EXPECT_TRUE(check_manifold(pieces).is_oriented_manifold());
  const PointMatrix C = cut_points(zero, X);
  // the zero set's boundary facets at t = 0
  const SimplexMatrix boundary = boundary_facets(pieces);
  std::vector<Index> end_rows;
  for (Index f = 0; f < boundary.rows(); ++f)
    if (C(boundary(f, 0), 3) == 0 && C(boundary(f, 1), 3) == 0 && C(boundary(f, 2), 3) == 0) end_rows.push_back(f);
  ASSERT_FALSE(end_rows.empty());
  SimplexMatrix end(static_cast<Index>(end_rows.size()), 3);
  std::set<Index> end_vertices;
  for (size_t i = 0; i < end_rows.size(); ++i) {
    end.row(static_cast<Index>(i)) = boundary.row(end_rows[i]);
    for (int c = 0; c < 3; ++c) {
      const ZeroCut& cut = zero.cuts()[boundary(end_rows[i], c)];
      if (cut.a == cut.b) end_vertices.insert(cut.a);
    }
  }
  // closed: every edge of the end surface in exactly two of its triangles, oppositely
  const ManifoldReport closed = check_manifold(end);
  EXPECT_EQ(closed.boundary_facets, 0);
  EXPECT_TRUE(closed.is_oriented_manifold());
  for (Index i = 0; i < 6; ++i) EXPECT_TRUE(end_vertices.count(i)) << "axis point " << i;
}

}  // namespace
}  // namespace animanifold
