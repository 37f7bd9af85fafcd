#include "animanifold/complex.hpp"
#include "animanifold/normals.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using namespace animanifold;

TEST(Complex, FacetRuleMatchesSection2_4) {
  // [A,B,C,D] → [B,C,D], [C,A,D], [A,B,D], [B,A,C]
  const Index tet[4] = {0, 1, 2, 3};
  const Index expected[4][3] = {{1, 2, 3}, {2, 0, 3}, {0, 1, 3}, {1, 0, 2}};
  for (int i = 0; i < 4; ++i) {
    Index f[3];
    facet(tet, 4, i, f);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f[c], expected[i][c]) << "facet " << i;
  }
}

TEST(Complex, FacetsOfPositiveTetPointOutward) {
  PointMatrix V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  SimplexMatrix S(1, 4);
  S << 0, 1, 2, 3;
  ASSERT_GT(signed_volumes(V, S)(0), 0);
  const SimplexMatrix F = facets(S);
  const PointMatrix N = simplex_normals(V, F);
  const Eigen::RowVector3d centroid = V.colwise().mean();
  for (int i = 0; i < 4; ++i) {
    const Eigen::RowVector3d face_centre =
        (V.row(F(i, 0)) + V.row(F(i, 1)) + V.row(F(i, 2))) / 3.0;
    EXPECT_GT(N.row(i).dot(face_centre - centroid), 0) << "facet " << i << " points inward";
  }
}

TEST(Complex, ClosedTetBoundaryIsConsistentlyOriented) {
  SimplexMatrix S(1, 4);
  S << 0, 1, 2, 3;
  const SimplexMatrix B = boundary_facets(S);
  const auto report = check_manifold(B);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 0);
  EXPECT_EQ(report.interior_facets, 6);
}

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
