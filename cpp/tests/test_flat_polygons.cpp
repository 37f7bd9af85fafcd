#include "animanifold/flat_polygons.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <utility>

using namespace animanifold;

namespace {

// A prism over the convex polygon `ring` (#n by 2, counter-clockwise) from
// z = -1 to z = 1, outward; each cap triangulated as a fan from its first rim
// vertex, or (`centre`) from a vertex at its centre, as Blender's "Triangle Fan".
void prism(const PointMatrix& ring, bool centre, PointMatrix& V, SimplexMatrix& F) {
  const Index n = static_cast<Index>(ring.rows());
  V.resize(2 * n + (centre ? 2 : 0), 3);
  for (Index i = 0; i < n; ++i) {
    V.row(i) << ring(i, 0), ring(i, 1), -1;
    V.row(i + n) << ring(i, 0), ring(i, 1), 1;
  }
  std::vector<std::array<Index, 3>> faces;
  for (Index i = 0; i < n; ++i) {
    const Index j = (i + 1) % n;
    faces.push_back({i, j, j + n});
    faces.push_back({i, j + n, i + n});
  }
  if (centre) {
    V.row(2 * n) << ring.col(0).mean(), ring.col(1).mean(), -1;
    V.row(2 * n + 1) << ring.col(0).mean(), ring.col(1).mean(), 1;
    for (Index i = 0; i < n; ++i) {
      faces.push_back({2 * n, (i + 1) % n, i});
      faces.push_back({2 * n + 1, i + n, (i + 1) % n + n});
    }
  } else {
    for (Index k = 1; k + 1 < n; ++k) {
      faces.push_back({0, k + 1, k});
      faces.push_back({n, k + n, k + 1 + n});
    }
  }
  F.resize(static_cast<Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) F.row(static_cast<Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
}

PointMatrix regular_polygon(Index n) {
  PointMatrix ring(n, 2);
  for (Index i = 0; i < n; ++i) ring.row(i) << std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n);
  return ring;
}

// Every directed edge once and its twin once: closed and consistently oriented.
void expect_closed_and_oriented(const SimplexMatrix& F) {
  std::map<std::pair<Index, Index>, int> edges;
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) ++edges[{F(f, c), F(f, (c + 1) % 3)}];
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1) << edge.first << "->" << edge.second;
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << edge.first << "->" << edge.second << " has no twin";
  }
}

// The signed volume enclosed, and the area, of (V, F).
std::pair<double, double> volume_and_area(const PointMatrix& V, const SimplexMatrix& F) {
  double volume = 0, area = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    volume += a.dot(b.cross(c)) / 6;
    area += (b - a).cross(c - a).norm() / 2;
  }
  return {volume, area};
}

}  // namespace

TEST(FlatPolygons, ACylindersCapsBecomeFansFromTheirCentresOnTheSameSurface) {
  PointMatrix V;
  SimplexMatrix F;
  prism(regular_polygon(64), false, V, F);
  const FannedMesh fanned = fan_flat_polygons(V, F);
  ASSERT_EQ(fanned.polygons, 2);
  // the input's vertices first, in order, then the two centres, in the caps' planes
  ASSERT_EQ(fanned.V.rows(), V.rows() + 2);
  EXPECT_EQ(fanned.V.topRows(V.rows()), V);
  for (Index p = 0; p < 2; ++p) {
    const Eigen::RowVector3d centre = fanned.V.row(V.rows() + p);
    EXPECT_NEAR(centre.head<2>().norm(), 0.0, 1e-15);
    EXPECT_EQ(std::abs(centre(2)), 1.0);
  }
  // the sides as they were, then a fan of 64 triangles per cap: all from a centre
  ASSERT_EQ(fanned.F.rows(), 128 + 2 * 64);
  EXPECT_EQ(fanned.F.topRows(128), F.topRows(128));
  for (Index f = 128; f < fanned.F.rows(); ++f) EXPECT_GE(fanned.F(f, 2), V.rows());
  expect_closed_and_oriented(fanned.F);
  const auto [volume, area] = volume_and_area(V, F);
  const auto [fanned_volume, fanned_area] = volume_and_area(fanned.V, fanned.F);
  EXPECT_NEAR(fanned_volume, volume, 1e-13 * volume);
  EXPECT_NEAR(fanned_area, area, 1e-13 * area);
  EXPECT_GT(volume, 0);
}

TEST(FlatPolygons, TurnedCapsWithRoundedCoordinatesAreStillFlat) {
  PointMatrix V;
  SimplexMatrix F;
  prism(regular_polygon(32), false, V, F);
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  // float32 coordinates turned in doubles, as Blender's objects: flat to ~1e-16, not exactly
  const PointMatrix turned = (V.cast<float>().cast<double>() * turn.transpose()).eval();
  const FannedMesh fanned = fan_flat_polygons(turned, F);
  EXPECT_EQ(fanned.polygons, 2);
  expect_closed_and_oriented(fanned.F);
}

TEST(FlatPolygons, QuadsFansFromACentreStraightCornersAndDentsAreLeftAlone) {
  PointMatrix V;
  SimplexMatrix F;
  // a cube: its sides are quads, below six corners
  prism((PointMatrix(4, 2) << 1, 1, -1, 1, -1, -1, 1, -1).finished(), false, V, F);
  EXPECT_EQ(fan_flat_polygons(V, F).polygons, 0);
  // Blender's "Triangle Fan" caps: a vertex inside already
  prism(regular_polygon(64), true, V, F);
  FannedMesh same = fan_flat_polygons(V, F);
  EXPECT_EQ(same.polygons, 0);
  EXPECT_EQ(same.V, V);
  EXPECT_EQ(same.F, F);
  // a hexagon with a straight corner (a row of squares' side has only such
  // corners), its caps fans from a corner that sees every other
  prism((PointMatrix(6, 2) << 1, 1.5, 0, 1, 0, 0, 1, 0, 2, 0, 2, 1).finished(), false, V, F);
  EXPECT_EQ(fan_flat_polygons(V, F).polygons, 0);
  // a dented hexagon, its caps fans from the reflex corner (each triangle positive)
  prism((PointMatrix(6, 2) << 1, 0.8, 0, 2, -0.5, 1, 0, 0, 2, 0, 2, 2).finished(), false, V, F);
  EXPECT_EQ(fan_flat_polygons(V, F).polygons, 0);
  // fewer corners than asked for
  prism(regular_polygon(8), false, V, F);
  EXPECT_EQ(fan_flat_polygons(V, F, 9).polygons, 0);
  EXPECT_EQ(fan_flat_polygons(V, F, 8).polygons, 2);
}

TEST(FlatPolygons, AGentlyCurvedSurfaceIsNotFlat) {
  // the bottom cap's rim bent by up to 1e-6 of the size (z += 1e-6 x^2): no
  // two of its triangles in one plane
  PointMatrix V;
  SimplexMatrix F;
  prism(regular_polygon(16), false, V, F);
  for (Index i = 0; i < 16; ++i) V(i, 2) += 1e-6 * V(i, 0) * V(i, 0);
  const FannedMesh fanned = fan_flat_polygons(V, F);
  EXPECT_EQ(fanned.polygons, 1);  // the top only
  expect_closed_and_oriented(fanned.F);
}
