// TriangleDistance (surface_distance.hpp): one search tree answers many
// queries with the distances distances_to_surface gives; an empty mesh is
// infinitely far; bad input is refused.
#include "animanifold/errors.hpp"
#include "animanifold/surface_distance.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace animanifold;

TEST(SurfaceDistance, OneTreeAnswersManyQueriesAsTheOneCallDoes) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  const TriangleDistance distance(V, F);
  PointMatrix points(4, 3);
  points << 0, 0, 0, 3, 0, 0, 1, 0, 0, 0.2, 0.2, 0.2;
  for (int round = 0; round < 2; ++round) {
    const Eigen::VectorXd d = distance(points);
    EXPECT_EQ(d, distances_to_surface(points, V, F));
    EXPECT_NEAR(d(0), 1 / std::sqrt(3.0), 1e-15);  // the centre to a face of the unit octahedron
    EXPECT_NEAR(d(1), 2.0, 1e-15);                 // beyond a vertex
    EXPECT_NEAR(d(2), 0.0, 1e-15);                 // on a vertex
  }
}

TEST(SurfaceDistance, AMeshWithoutAProperFaceIsInfinitelyFar) {
  PointMatrix V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // one face, flat
  SimplexMatrix F(1, 3);
  F << 0, 1, 2;
  const Eigen::VectorXd d = TriangleDistance(V, F)(PointMatrix::Zero(2, 3));
  EXPECT_TRUE(std::isinf(d(0)) && std::isinf(d(1)));
}

TEST(SurfaceDistance, BadInputIsRefused) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  SimplexMatrix outside = F;
  outside(0, 0) = 99;
  EXPECT_THROW(TriangleDistance(V, outside), InputError);
  EXPECT_THROW(TriangleDistance(V.leftCols(2), F), InputError);
  EXPECT_THROW(TriangleDistance(V, F)(PointMatrix::Zero(1, 2)), InputError);
}
