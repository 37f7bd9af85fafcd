#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
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

TEST(Complex, AdjacencyIsSymmetricAndBoundaryIsMinusOne) {
  // Two tets sharing the facet (1,2,3), oppositely oriented.
  SimplexMatrix S(2, 4);
  S << 0, 1, 2, 3, 4, 2, 1, 3;
  const auto report = check_manifold(S);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.interior_facets, 1);
  const FacetAdjacency a = facet_adjacency(S);
  EXPECT_EQ(a.neighbour(0, 0), 1);  // facet 0 of tet 0 drops vertex 0: (1,2,3)
  EXPECT_EQ(a.neighbour(1, 0), 0);  // facet 0 of tet 1 drops vertex 4: (2,1,3)
  EXPECT_EQ(a.opposite(0, 0), 0);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(a.neighbour(0, i), -1);
  // Same orientation on the shared facet is reported, and three tets on one facet throw.
  SimplexMatrix bad(2, 4);
  bad << 0, 1, 2, 3, 4, 1, 2, 3;
  EXPECT_EQ(check_manifold(bad).misoriented_facets, 1);
  SimplexMatrix fan(3, 4);
  fan << 0, 1, 2, 3, 4, 2, 1, 3, 5, 2, 1, 3;
  EXPECT_EQ(check_manifold(fan).nonmanifold_facets, 1);
  EXPECT_THROW(facet_adjacency(fan), InputError);
}

TEST(Complex, PolygonOrientationUsesVertexSigns) {
  SimplexMatrix ring(3, 2);
  ring << 0, 1, 1, 2, 2, 0;
  EXPECT_TRUE(check_manifold(ring).is_oriented_manifold());
  SimplexMatrix flipped(3, 2);
  flipped << 0, 1, 2, 1, 2, 0;  // edge 1 runs backwards
  EXPECT_EQ(check_manifold(flipped).misoriented_facets, 2);
}
