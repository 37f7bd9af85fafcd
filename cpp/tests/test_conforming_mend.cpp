// Mending a constrained-only TetGen result (conforming_mend.hpp) on small
// known cases.
#include "animanifold/conforming_mend.hpp"

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

}  // namespace
}  // namespace animanifold
