// Wedge products and simplex / vertex normals (normals.hpp).
#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"
#include "fixtures.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

using namespace animanifold;

TEST(Normals, WedgeInR3IsCross) {
  PointMatrix rows(2, 3);
  rows << 1, 2, 3, -4, 5, 0.5;
  const Eigen::Vector3d a(1, 2, 3), b(-4, 5, 0.5);
  EXPECT_NEAR((wedge(rows) - a.cross(b)).norm(), 0, 1e-14);
}

TEST(Normals, WedgeInR4IsOrthogonalWithVolumeLength) {
  PointMatrix rows(3, 4);
  rows << 1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 3, 0;
  const Eigen::VectorXd n = wedge(rows);
  EXPECT_NEAR(std::abs(n(3)), 6.0, 1e-14);
  EXPECT_NEAR(n.head<3>().norm(), 0.0, 1e-14);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(rows.row(r).dot(n), 0.0, 1e-14);
}

TEST(Normals, SphereVertexNormalsAreRadial) {
  // Octahedron: area-weighted normals at the six vertices are exactly radial.
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  const PointMatrix N = vertex_normals(V, F);
  for (int v = 0; v < 6; ++v) EXPECT_NEAR((N.row(v) - V.row(v)).norm(), 0, 1e-14);
  const PointMatrix dropped = drop_component(N, 2);
  EXPECT_NEAR(dropped.row(0).norm(), 1.0, 1e-14);
  EXPECT_NEAR(dropped.row(4).norm(), 0.0, 1e-14);  // the pole's normal was all z
}

TEST(Normals, HugeAndTinyFramesHaveTheUnitFramesNormals) {
  // Octahedron frame: cross products of 1e154-sized edges overflow unless scaled first.
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  const PointMatrix unit = frame_vertex_normals(V, F);
  for (const double scale : {1e154, 1e300, 1e-170}) {
    const PointMatrix scaled = frame_vertex_normals(V * scale, F);
    EXPECT_TRUE(scaled.allFinite()) << scale;
    EXPECT_LT((scaled - unit).cwiseAbs().maxCoeff(), 1e-15) << scale;
  }
}

TEST(Normals, IndicesOutsideThePointsAreRefused) {
  PointMatrix V = PointMatrix::Identity(3, 3);
  SimplexMatrix F(1, 3);
  F << 0, 1, 100000000;
  EXPECT_THROW(frame_vertex_normals(V, F), InputError);
  F(0, 2) = -1000000;
  EXPECT_THROW(vertex_normals(V, F), InputError);
}
