// TriangleDistance (surface_distance.hpp): one search tree answers many
// queries with the distances distances_to_surface gives; the farthest of
// many points is their largest distance, to the bit; an empty mesh is
// infinitely far; bad input is refused.
#include "animanifold/errors.hpp"
#include "animanifold/surface_distance.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

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

namespace {

// A bumpy closed surface: the octahedron's faces split in four `rounds`
// times, each vertex pushed out to a random radius in [0.7, 1.3].
void bumpy_sphere(int rounds, unsigned seed, PointMatrix& V, SimplexMatrix& F) {
  fixtures::octahedron(V, F);
  fixtures::subdivide(V, F, rounds);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> radius(0.7, 1.3);
  for (Index v = 0; v < V.rows(); ++v) V.row(v) *= radius(random) / V.row(v).norm();
}

}  // namespace

TEST(SurfaceDistance, TheFarthestIsTheLargestDistanceToTheBit) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    PointMatrix V;
    SimplexMatrix F;
    bumpy_sphere(3, seed, V, F);
    const TriangleDistance distance(V, F);
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> coordinate(-2.0, 2.0), share(0.0, 1.0);
    // Points anywhere, and points on the surface (distance about 0).
    PointMatrix points(3000, 3);
    for (Index p = 0; p < points.rows(); ++p) {
      if (p % 3) {
        points.row(p) << coordinate(random), coordinate(random), coordinate(random);
        continue;
      }
      const Index f = static_cast<Index>(random() % F.rows());
      const double u = share(random), v = share(random) * (1 - u);
      points.row(p) = (1 - u - v) * V.row(F(f, 0)) + u * V.row(F(f, 1)) + v * V.row(F(f, 2));
    }
    const Eigen::VectorXd d = distance(points);
    EXPECT_EQ(distance.farthest(points), d.maxCoeff()) << "seed " << seed;
    // Nearest first: every point may raise the largest, the farthest comes
    // last (not among the points measured first); and farthest first.
    std::vector<Index> order(static_cast<size_t>(points.rows()));
    std::iota(order.begin(), order.end(), Index{0});
    std::sort(order.begin(), order.end(), [&](Index a, Index b) { return d(a) < d(b); });
    PointMatrix nearest_first(points.rows(), 3), farthest_first(points.rows(), 3);
    for (Index i = 0; i < points.rows(); ++i) {
      nearest_first.row(i) = points.row(order[i]);
      farthest_first.row(points.rows() - 1 - i) = points.row(order[i]);
    }
    EXPECT_EQ(distance.farthest(nearest_first), d.maxCoeff()) << "seed " << seed;
    EXPECT_EQ(distance.farthest(farthest_first), d.maxCoeff()) << "seed " << seed;
  }
}

TEST(SurfaceDistance, TheFarthestOfPointsAtOneDistanceIsThatDistance) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  // Two beyond each of the six vertices, and the centre (1 / sqrt 3 from every face).
  PointMatrix points(7, 3);
  points << 0, 0, 0, 3, 0, 0, -3, 0, 0, 0, 3, 0, 0, -3, 0, 0, 0, 3, 0, 0, -3;
  const TriangleDistance distance(V, F);
  EXPECT_EQ(distance.farthest(points), distance(points).maxCoeff());
  EXPECT_NEAR(distance.farthest(points), 2.0, 1e-15);
  EXPECT_EQ(distance.farthest(PointMatrix(0, 3)), 0.0);
  PointMatrix flat(3, 3);
  flat << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  SimplexMatrix one_face(1, 3);
  one_face << 0, 1, 2;
  EXPECT_TRUE(std::isinf(TriangleDistance(flat, one_face).farthest(PointMatrix::Zero(2, 3))));
  EXPECT_THROW(distance.farthest(PointMatrix::Zero(1, 2)), InputError);
}
