// check_convex_cover (convex_cover.hpp): a Delaunay triangulation tiles the
// convex hull of its points once (R^3), and a slab of prisms over it tiles
// the hull times the slab's interval (R^4); a missing cell, a flipped one, a
// second layer or a fold each break the certificate and are counted.
#include "convex_cover.hpp"

#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"
#include "morph_field_internal.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace animanifold;

namespace {

// The 2^d corners of [0, 1]^d and `inside` random points strictly inside.
PointMatrix box_points(int d, int inside, unsigned seed) {
  const int corners = 1 << d;
  PointMatrix P(corners + inside, d);
  for (int c = 0; c < corners; ++c)
    for (int axis = 0; axis < d; ++axis) P(c, axis) = (c >> axis) & 1;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(0.05, 0.95);
  for (int r = corners; r < P.rows(); ++r)
    for (int axis = 0; axis < d; ++axis) P(r, axis) = coordinate(random);
  return P;
}

SimplexMatrix without_row(const SimplexMatrix& S, Index dropped) {
  SimplexMatrix out(S.rows() - 1, S.cols());
  out << S.topRows(dropped), S.bottomRows(S.rows() - dropped - 1);
  return out;
}

// The simplex of S with a corner farthest from the box's faces (inside).
Index inner_simplex(const PointMatrix& P, const SimplexMatrix& S) {
  for (Index s = 0; s < S.rows(); ++s) {
    bool inner = true;
    for (int c = 0; c < S.cols() && inner; ++c)
      for (int axis = 0; axis < P.cols(); ++axis) inner = inner && P(S(s, c), axis) > 0 && P(S(s, c), axis) < 1;
    if (inner) return s;
  }
  return -1;
}

}  // namespace

TEST(ConvexCover, ADelaunayTriangulationTilesItsHullOnce) {
  // Points in a ball: the hull has many faces, none of them the box's.
  PointMatrix P = box_points(3, 200, 13u).bottomRows(200);
  for (Index r = 0; r < P.rows(); ++r) {
    const Eigen::RowVector3d offset = P.row(r) - Eigen::RowVector3d::Constant(0.5);
    if (offset.norm() > 0.45) P.row(r) = Eigen::RowVector3d::Constant(0.5) + 0.45 * offset.normalized();
  }
  const SimplexMatrix S = delaunay_exact(P).simplices;
  const ConvexCover cover = check_convex_cover(P, S);
  EXPECT_TRUE(cover.covers_once()) << cover.failure();
  EXPECT_EQ(cover.simplices, S.rows());
  EXPECT_NEAR(cover.volume_ratio, 1.0, 1e-12);
  EXPECT_EQ(cover.failure(), "");
}

// The prisms over `cells` (over n points) between their copies at times a
// and b, each cut into four positive 4-simplices (prism_simplices).
void prism_slab(const PointMatrix& P, const SimplexMatrix& cells, double a, double b, PointMatrix& layers,
                SimplexMatrix& slab) {
  const Index n = P.rows();
  layers.resize(2 * n, 4);
  layers << P, Eigen::VectorXd::Constant(n, a), P, Eigen::VectorXd::Constant(n, b);
  slab.resize(4 * cells.rows(), 5);
  for (Index c = 0; c < cells.rows(); ++c) {
    morph_field::Simplex4 prism[4];
    morph_field::prism_simplices(cells.row(c).data(), 0, n, prism);
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 5; ++j) slab(4 * c + k, j) = prism[k][j];
  }
}

TEST(ConvexCover, ASlabOfPrismsTilesTheHullTimesItsInterval) {
  const PointMatrix P = box_points(3, 60, 17u);
  PointMatrix layers;
  SimplexMatrix slab;
  prism_slab(P, delaunay_exact(P).simplices, 0.25, 0.75, layers, slab);
  const ConvexCover cover = check_convex_cover(layers, slab);
  EXPECT_TRUE(cover.covers_once()) << cover.failure();
  EXPECT_NEAR(cover.volume_ratio, 1.0, 1e-12);
  // Without one prism's simplices the slab has a hole through it.
  const ConvexCover holed = check_convex_cover(layers, SimplexMatrix(slab.bottomRows(slab.rows() - 4)));
  EXPECT_FALSE(holed.covers_once());
  EXPECT_GT(holed.stray_boundary_facets, 0);
}

TEST(ConvexCover, AMissingCellLeavesFacetsInsideTheRegionAndVolumeShort) {
  for (const int d : {3, 4}) {
    const PointMatrix P = box_points(d, 60, 11u);
    const SimplexMatrix S = delaunay_exact(P).simplices;
    const Index hole = inner_simplex(P, S);
    ASSERT_GE(hole, 0);
    const ConvexCover cover = check_convex_cover(P, without_row(S, hole));
    EXPECT_FALSE(cover.covers_once());
    EXPECT_EQ(cover.stray_boundary_facets, d + 1) << "R^" << d;
    EXPECT_LT(cover.volume_ratio, 1.0);
    EXPECT_NE(cover.failure().find("boundary facets inside the region"), std::string::npos) << cover.failure();
  }
}

TEST(ConvexCover, AFlippedCellIsNotPositiveAndItsFacetsDoNotMatch) {
  const PointMatrix P = box_points(3, 40, 3u);
  SimplexMatrix S = delaunay_exact(P).simplices;
  const Index flipped = inner_simplex(P, S);
  std::swap(S(flipped, 0), S(flipped, 1));
  const ConvexCover cover = check_convex_cover(P, S);
  EXPECT_FALSE(cover.covers_once());
  EXPECT_EQ(cover.not_positive, 1);
  EXPECT_EQ(cover.unmatched_facets, 4);
}

TEST(ConvexCover, ASecondLayerIsCaughtByItsFacetsAndItsVolume) {
  const PointMatrix P = box_points(3, 40, 5u);
  const SimplexMatrix S = delaunay_exact(P).simplices;
  SimplexMatrix twice(2 * S.rows(), 4);
  twice << S, S;
  const ConvexCover cover = check_convex_cover(P, twice);
  EXPECT_FALSE(cover.covers_once());
  EXPECT_GT(cover.unmatched_facets, 0);
  EXPECT_NEAR(cover.volume_ratio, 2.0, 1e-12);
}

TEST(ConvexCover, APointMovedThroughItsNeighboursFoldsTheTriangulation) {
  PointMatrix P = box_points(3, 40, 9u);
  const SimplexMatrix S = delaunay_exact(P).simplices;
  // An inner point pushed through the far side of its star: some of its
  // cells turn over, and the rest overlap them.
  const Index moved = S(inner_simplex(P, S), 0);
  P.row(moved) = Eigen::RowVector3d(1, 1, 1) - P.row(moved);
  const ConvexCover cover = check_convex_cover(P, S);
  EXPECT_FALSE(cover.covers_once());
  EXPECT_GT(cover.not_positive, 0);
}

TEST(ConvexCover, BadInputIsRefusedWithAMessage) {
  const PointMatrix P = box_points(3, 4, 1u);
  SimplexMatrix S(1, 4);
  S << 0, 1, 2, 99;
  EXPECT_THROW(check_convex_cover(P, S), InputError);
  EXPECT_THROW(check_convex_cover(PointMatrix::Zero(4, 2), SimplexMatrix::Zero(1, 3)), InputError);
  EXPECT_THROW(check_convex_cover(P, SimplexMatrix::Zero(1, 3)), InputError);
}
