// Mending a constrained-only TetGen result (conforming_mend.hpp) on small
// known cases.
#include "animanifold/conforming_mend.hpp"
#include "animanifold/delaunay.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "fixtures.hpp"

namespace animanifold {
namespace {

using fixtures::at;
using fixtures::normal;

// An equilateral input triangle (side 4, in z = 0) with its edges split in
// fifths, fanned from its centre (point 15). A circumcentre inside an unsplit
// triangle always lies in one edge's diametral circle (it sees the three
// edges under angles summing to 360°); with the edges split, the piece on the
// middle of the bottom edge has its circumcentre in none.
ConstraintSurface fanned_triangle() {
  ConstraintSurface s;
  const Eigen::Vector3d corner[3] = {{0, 0, 0}, {4, 0, 0}, {2, 2 * std::sqrt(3.0), 0}};
  s.points.resize(16, 3);
  for (int e = 0; e < 3; ++e)
    for (int k = 0; k < 5; ++k)
      s.points.row(5 * e + k) = (corner[e] + 0.2 * k * (corner[(e + 1) % 3] - corner[e])).transpose();
  s.points.row(15) = ((corner[0] + corner[1] + corner[2]) / 3).transpose();
  for (Index i = 0; i < 15; ++i) {
    s.faces.push_back({15, i, (i + 1) % 15});
    s.parent.push_back(0);
  }
  s.inner.assign(s.faces.size(), {});
  return s;
}

TEST(ConformingMend, ACircumcentreWellInsideGoesIntoItsPiece) {
  ConstraintSurface s = fanned_triangle();
  const ConstraintSurface before = s;
  // Piece 2 stands on (1.6, 0)-(2.4, 0): its circumcentre (2, 0.51) lies
  // above that piece's diametral circle (radius 0.4), inside the piece.
  const MendReport report = mend_non_delaunay_faces(s, {2});
  EXPECT_EQ(report.inner_points, 1);
  EXPECT_EQ(report.edge_points, 0);
  ASSERT_EQ(s.points.rows(), 17);
  EXPECT_EQ(s.faces, before.faces);
  ASSERT_EQ(s.inner[2].size(), 1u);
  EXPECT_EQ(s.inner[2][0], 16);
  const Eigen::Vector3d c = at(s.points, 16);
  const double r = (c - at(s.points, s.faces[2][0])).norm();
  for (int k = 1; k < 3; ++k) EXPECT_NEAR((c - at(s.points, s.faces[2][k])).norm(), r, 1e-12);
  EXPECT_EQ(c.z(), 0.0);
}

TEST(ConformingMend, ACircumcentreOutsideTheInputTriangleSplitsItsBoundary) {
  ConstraintSurface s = fanned_triangle();
  // Piece 0, (centre, corner 0, (0.8, 0)), is obtuse enough that its
  // circumcentre (0.4, 1.62) lies beyond the input triangle's left edge:
  // nothing goes outside; the boundary piece nearest it is split.
  const MendReport report = mend_non_delaunay_faces(s, {0});
  EXPECT_EQ(report.inner_points, 0);
  EXPECT_GE(report.edge_points, 1);
  EXPECT_GT(s.faces.size(), 15u);
  for (const Index parent : s.parent) EXPECT_EQ(parent, 0);
  for (size_t f = 0; f < s.faces.size(); ++f) EXPECT_GT(normal(s.points, s.faces[f]).z(), 0) << "piece " << f;
}

TEST(ConformingMend, AnEncroachedEdgeIsSplitInBothTrianglesBesideIt) {
  // Two input triangles on edge 0-1. The first is tall enough that its
  // circumcentre (1, -0.225, 0) lies in that edge's diametral circle.
  ConstraintSurface s;
  s.points.resize(5, 3);
  s.points << 0, 0, 0, 2, 0, 0, 1, 0.8, 0, 1, -1, 0.5, 1.25, -0.25, 0.125;
  s.faces = {{0, 1, 2}, {1, 0, 3}};
  s.parent = {0, 1};
  s.inner = {{}, {4}};  // point 4 lies in the second triangle, nearer corner 1
  const PointMatrix P0 = s.points;
  const auto faces0 = s.faces;
  const MendReport report = mend_non_delaunay_faces(s, {0});
  EXPECT_EQ(report.edge_points, 1);
  EXPECT_EQ(report.inner_points, 0);
  ASSERT_EQ(s.points.rows(), 6);
  EXPECT_TRUE(at(s.points, 5).isApprox(Eigen::Vector3d(1, 0, 0)));
  ASSERT_EQ(s.faces.size(), 4u);
  int pieces[2] = {0, 0};
  for (size_t f = 0; f < s.faces.size(); ++f) {
    const Index parent = s.parent[f];
    ++pieces[parent];
    EXPECT_NE(std::find(s.faces[f].begin(), s.faces[f].end(), 5), s.faces[f].end());  // every piece has the midpoint
    EXPECT_GT(normal(s.points, s.faces[f]).dot(normal(P0, faces0[parent])), 0) << "piece " << f << " turned over";
    const bool holds_4 = !s.inner[f].empty();
    if (holds_4) {
      EXPECT_EQ(parent, 1);
      EXPECT_NE(std::find(s.faces[f].begin(), s.faces[f].end(), 1), s.faces[f].end());
    }
  }
  EXPECT_EQ(pieces[0], 2);
  EXPECT_EQ(pieces[1], 2);
}

// TetGen takes points nearer each other than a few 1e-9 of their bounding
// box for one, drops the second and numbers its output without it. Blender's
// cylinder -> cube met this: two bad faces on the cocircular cap asked for
// circumcentres 2e-8 apart, and the morph failed.
TEST(ConformingMend, NoPointGoesWhereTetGenWouldTakeItForOneAlreadyThere) {
  ConstraintSurface probe = fanned_triangle();
  mend_non_delaunay_faces(probe, {2});
  const Eigen::Vector3d centre = at(probe.points, 16);  // piece 2's circumcentre, (2, 0.51)
  for (const double apart : {2e-8, 1e-3}) {
    // A point of an earlier round lies `apart` from where piece 2 asks for one.
    ConstraintSurface s = fanned_triangle();
    s.points.conservativeResize(17, 3);
    s.points.row(16) = (centre + Eigen::Vector3d(apart, 0, 0)).transpose();
    s.inner[2] = {16};
    const MendReport report = mend_non_delaunay_faces(s, {2});
    const bool one_point_to_tetgen = apart < 1e-6;
    EXPECT_EQ(report.inner_points, one_point_to_tetgen ? 0 : 1) << apart << " from a point there";
    EXPECT_EQ(s.points.rows(), one_point_to_tetgen ? 17 : 18);
  }
}

TEST(ConformingMend, AnEdgeWhoseMiddleHoldsAPointAlreadyStaysWhole) {
  // Two triangles on edge 0-1, and a point of an earlier round 2e-8 from
  // the edge's middle (1, 0, 0): splitting there would give TetGen the same
  // point twice, so neither triangle is split.
  ConstraintSurface s;
  s.points.resize(5, 3);
  s.points << 0, 0, 0, 2, 0, 0, 1, 0.8, 0, 1, -1, 0, 1 + 2e-8, 0, 0;
  s.faces = {{0, 1, 2}, {1, 0, 3}};
  s.parent = {0, 1};
  s.inner = {{}, {}};
  const auto faces = s.faces;
  const MendReport report = split_surface_edges(s, {{0, 1}});
  EXPECT_EQ(report.added(), 0);
  EXPECT_EQ(s.points.rows(), 5);
  EXPECT_EQ(s.faces, faces);
}

// A unit square a b c d in z = 0 (its corners cocircular), surface faces
// abc and acd on diagonal ac, and points 4 and 5 above and below it.
PointMatrix square_with_apexes() {
  PointMatrix P(6, 3);
  P << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1, 0.5, 0.5, -1;
  return P;
}

TEST(FlatSurfaceCells, FindTheTetBetweenAPlanarQuadsDiagonalsAndNameItsSurfaceDiagonal) {
  const PointMatrix P = square_with_apexes();
  SimplexMatrix faces(2, 3);
  faces << 0, 1, 2, 0, 2, 3;
  SimplexMatrix tets(4, 4);
  tets << 0, 1, 2, 3,  // flat: between diagonal 0-2 (the surface's) and 1-3
      0, 1, 2, 4,      // not all corners on the surface
      0, 1, 3, 5,      //
      1, 2, 3, 5;
  const FlatCells flat = flat_surface_cells(tets, P, faces);
  EXPECT_EQ(flat.cells, 1);
  ASSERT_EQ(flat.diagonals.size(), 1u);
  EXPECT_EQ(flat.diagonals[0], (std::array<Index, 2>{0, 2}));
  EXPECT_EQ(flat.without_surface_diagonal, 0);

  // Lifted off the plane by far more than rounding, the same four corners
  // make a proper tet: not flat.
  PointMatrix lifted = P;
  lifted(3, 2) = 1e-3;
  EXPECT_EQ(flat_surface_cells(tets, lifted, faces).cells, 0);

  // A flat cell neither of whose diagonals the surface holds (four coplanar
  // points across a step: the surface is the pyramid's sides from 4 here) is
  // counted apart, and the longest of its sides that the surface holds is
  // named instead (the first of equals): its middle lies inside every sphere
  // through the four corners.
  SimplexMatrix sides(4, 3);
  sides << 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4;
  const FlatCells other = flat_surface_cells(tets.topRows(1), P, sides);
  EXPECT_EQ(other.cells, 1);
  ASSERT_EQ(other.diagonals.size(), 1u);
  EXPECT_EQ(other.diagonals[0], (std::array<Index, 2>{0, 1}));
  EXPECT_EQ(other.without_surface_diagonal, 1);

  // With no edge of the cell on the surface, nothing is named.
  SimplexMatrix apart(4, 3);
  apart << 0, 4, 5, 1, 4, 5, 2, 4, 5, 3, 4, 5;
  const FlatCells none = flat_surface_cells(tets.topRows(1), P, apart);
  EXPECT_EQ(none.cells, 1);
  EXPECT_TRUE(none.diagonals.empty());
}

TEST(FlatSurfaceCells, SplittingTheSurfaceDiagonalSplitsBothFacesBesideIt) {
  ConstraintSurface s;
  s.points = square_with_apexes();
  s.faces = {{0, 1, 2}, {0, 2, 3}};
  s.parent = {7, 9};
  const MendReport report = split_surface_edges(s, {{2, 0}, {1, 3}});  // 1-3 is no edge of the surface
  EXPECT_EQ(report.edge_points, 1);
  ASSERT_EQ(s.points.rows(), 7);
  EXPECT_TRUE(at(s.points, 6).isApprox(Eigen::Vector3d(0.5, 0.5, 0)));
  ASSERT_EQ(s.faces.size(), 4u);
  int pieces[2] = {0, 0};
  for (size_t f = 0; f < s.faces.size(); ++f) {
    ++pieces[s.parent[f] == 7 ? 0 : 1];
    EXPECT_NE(std::find(s.faces[f].begin(), s.faces[f].end(), 6), s.faces[f].end());
    EXPECT_GT(normal(s.points, s.faces[f]).z(), 0) << "piece " << f << " turned over";
  }
  EXPECT_EQ(pieces[0], 2);
  EXPECT_EQ(pieces[1], 2);
}

// A torus of revolution (major radius 1, minor 0.3), `around` by `across`
// quads, each split on the same diagonal: every quad is an isosceles
// trapezoid, four cocircular points. Then, as free points (rows past the
// surface's), a point inside and one outside each vertex, as a morph puts
// around its inputs: with none inside the tube, the pieces of split quads
// make flat cells of their own (conforming_delaunay_3d.cpp).
void torus_of_revolution(int around, int across, PointMatrix& V, SimplexMatrix& F) {
  const double pi = 3.14159265358979323846;
  const Index n = static_cast<Index>(around) * across;
  V.resize(3 * n, 3);
  F.resize(2 * n, 3);
  auto id = [&](int i, int j) { return static_cast<Index>((i % around) * across + j % across); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const double u = 2 * pi * i / around, v = 2 * pi * j / across;
      for (int layer = 0; layer < 3; ++layer) {
        // off the surface by a tenth of the tube, turned a little so that
        // the free points are not cocircular in their turn
        const double minor = 0.3 + (layer == 0 ? 0.0 : layer == 1 ? 0.03 : -0.03);
        const double w = v + (layer == 0 ? 0.0 : 0.1 * pi / across), r = 1 + minor * std::cos(w);
        const double turn = u + (layer == 0 ? 0.0 : 0.07 * pi / around * layer);
        V.row(layer * n + id(i, j)) << r * std::cos(turn), r * std::sin(turn), minor * std::sin(w);
      }
      const Index q = 2 * id(i, j);
      F.row(q) << id(i, j), id(i + 1, j), id(i + 1, j + 1);
      F.row(q + 1) << id(i, j), id(i + 1, j + 1), id(i, j + 1);
    }
}

TEST(FlatSurfaceCells, AConformingTetrahedralizationMendedForThemHasNone) {
  PointMatrix V;
  SimplexMatrix F;
  torus_of_revolution(24, 12, V, F);
  const ConformingDelaunay c = conforming_delaunay_3d(V, F, {}, 0, /*mend_flat_cells=*/true);
  ASSERT_TRUE(c.is_delaunay);
  EXPECT_EQ(c.flat_cells, 0);
  EXPECT_EQ(flat_surface_cells(c.simplices, c.points, c.constraints).cells, 0);
  EXPECT_EQ(missing_facets(c.simplices, c.constraints).size(), 0);
  EXPECT_LE(c.flat_cell_points, c.mended_points);
}

}  // namespace
}  // namespace animanifold
