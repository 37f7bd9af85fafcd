// The pieces of the skeleton morph (morph_skeleton.hpp), the exact Delaunay
// fill and the self-intersection test, on small known configurations.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "morph_skeleton.hpp"
#include "animanifold/perturbation.hpp"
#include "animanifold/self_intersection.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>

namespace animanifold {
namespace {

// Random points in R^4 on two planes t = 0 and t = 1, like a morph's fill.
PointMatrix two_planes(int per_plane, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  PointMatrix P(2 * per_plane, 4);
  for (int r = 0; r < 2 * per_plane; ++r) P.row(r) << g(rng), g(rng), g(rng), r < per_plane ? 0.0 : 1.0;
  return P;
}

double total_volume(const PointMatrix& P, const SimplexMatrix& A) { return signed_volumes(P, A).sum(); }

TEST(MorphSkeleton, SplittingFacesKeepsTheFillPositiveAndItsVolume) {
  PointMatrix P = two_planes(30, 1);
  SimplexMatrix A = delaunay_exact(P).simplices;
  const double before = total_volume(P, A);
  const SimplexMatrix boundary_before = boundary_facets(A);
  // An edge, a triangle and a cell of the t = 0 plane's triangulation: faces of the fill, none
  // holding an earlier one (split_faces' precondition: a split face is gone).
  std::vector<std::vector<Index>> faces;
  auto holds = [](const std::vector<Index>& big, const std::vector<Index>& small) {
    for (const Index v : small)
      if (std::find(big.begin(), big.end(), v) == big.end()) return false;
    return true;
  };
  for (Index s = 0; s < A.rows() && faces.size() < 3; ++s) {
    std::vector<Index> in_plane;
    for (int c = 0; c < 5; ++c)
      if (A(s, c) < 30) in_plane.push_back(A(s, c));
    if (in_plane.size() < faces.size() + 2) continue;
    in_plane.resize(faces.size() + 2);
    bool fresh = true;
    for (const auto& earlier : faces) fresh = fresh && !holds(in_plane, earlier);
    if (fresh) faces.push_back(in_plane);
  }
  ASSERT_EQ(faces.size(), 3u);
  const Index points_before = P.rows();
  const IndexVector added = split_faces(P, A, faces);
  ASSERT_EQ(added.size(), 3);
  EXPECT_EQ(P.rows(), points_before + 3);
  for (Index a = 0; a < added.size(); ++a) EXPECT_EQ(P(added(a), 3), 0.0);  // on the plane of its face
  const Eigen::VectorXd volumes = signed_volumes(P, A);
  EXPECT_GT(volumes.minCoeff(), 0.0);
  EXPECT_NEAR(volumes.sum(), before, 1e-9 * before);  // a split refines, it neither adds nor removes
  EXPECT_EQ(check_manifold(boundary_facets(A)).nonmanifold_facets, 0);
  EXPECT_GT(boundary_facets(A).rows(), boundary_before.rows());  // the cell lay on the boundary
}

TEST(MorphSkeleton, PerturbationAlongHullFacesLeavesFlatSidesAlone) {
  // A 2x2x2 box's corners, a point inside its top face, one on its edge along
  // x at y = z = 0, and one inside the box.
  PointMatrix V(12, 3);
  for (int c = 0; c < 8; ++c) V.row(c) << 2.0 * (c & 1), 2.0 * ((c >> 1) & 1), 2.0 * ((c >> 2) & 1);
  V.row(8) << 1.0, 0.7, 2.0;
  V.row(9) << 0.6, 0.0, 0.0;
  V.row(10) << 1.0, 1.0, 1.0;
  V.row(11) << 1.3, 2.0, 0.4;  // inside the side y = 2
  const double scale = 1e-3;
  const PointMatrix P = perturbed_along_hull_faces(V, scale, 7);
  // On a flat side (corners, a point inside a face, one on an edge): not
  // moved at all, so that segments in the sides stay parallel (moved within
  // its side, a voxel plate's grid stopped being parallel to a cube's edges
  // facing it, and the 4D hull's facet across them held flat tets).
  for (int v : {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11}) EXPECT_EQ(P.row(v), V.row(v)) << "point " << v;
  EXPECT_EQ(P.row(10), perturbed_by_position(V, scale, 7).row(10));  // inside: the plain perturbation
  EXPECT_NE(P.row(10), V.row(10));
  EXPECT_LE((P - V).cwiseAbs().maxCoeff(), scale);
}

TEST(MorphSkeleton, PerturbationAlongHullFacesLeavesCurvedHullCornersAlone) {
  // An octahedron's corners (every hull facet a triangle of three: no flat
  // side) and two points inside it. The corners stay (a sphere's corners
  // moved bent the hyperplane they share with a voxel plate's edge in R^4);
  // the inner points take the plain perturbation.
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  PointMatrix W(8, 3);
  W << V, 0.1, 0.2, 0.3, -0.2, 0.1, 0.0;
  const double scale = 1e-3;
  const PointMatrix P = perturbed_along_hull_faces(W, scale, 7);
  for (int v = 0; v < 6; ++v) EXPECT_EQ(P.row(v), W.row(v)) << "corner " << v;
  for (int v : {6, 7}) {
    EXPECT_EQ(P.row(v), perturbed_by_position(W, scale, 7).row(v));
    EXPECT_NE(P.row(v), W.row(v));
  }
}

TEST(MorphSkeleton, OnConvexHullFlagsCornersEdgeAndFacePointsOnly) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  PointMatrix points(5, 3);
  points << V.row(0), 0.5, 0.5, 0.0,  // a corner, the middle of an edge
      1.0 / 3, 1.0 / 3, 1.0 / 3,      // the centre of a facet
      0.1, 0.1, 0.1,                  // inside
      1.0, 1.0, 0.0;                  // outside, in no facet's plane
  const std::vector<bool> on = on_convex_hull(points, V);
  EXPECT_EQ(on, (std::vector<bool>{true, true, true, false, false}));
  EXPECT_EQ(on_convex_hull(PointMatrix::Zero(2, 2), PointMatrix::Zero(4, 2)), (std::vector<bool>{false, false}));
}

TEST(MorphSkeleton, DepthInHullIsTheDistanceToTheNearestFacet) {
  PointMatrix V, points(3, 3);
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  points << 0, 0, 0, 0.25, 0, 0, 2, 0, 0;
  const Eigen::VectorXd depth = depth_in_hull(points, V);
  EXPECT_NEAR(depth(0), 1 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(depth(1), 0.75 / std::sqrt(3.0), 1e-12);
  EXPECT_LT(depth(2), 0.0);
}

TEST(SelfIntersection, FindsCrossingFacesAndNotNeighbours) {
  PointMatrix V, two(12, 3);
  SimplexMatrix F, both(16, 3);
  fixtures::octahedron(V, F);
  EXPECT_TRUE(self_intersections(V, F).empty());
  two << V, V.rowwise() + Eigen::RowVector3d(0.5, 0.2, 0.1);
  both << F, F.array() + 6;
  const auto pairs = self_intersections(two, both, 0);
  ASSERT_FALSE(pairs.empty());
  for (const auto& [a, b] : pairs) EXPECT_TRUE(a < 8 && b >= 8);  // one face of each copy
  // 2D: a pentagram's edges cross; a pentagon's do not.
  PointMatrix star(5, 2), gon(5, 2);
  SimplexMatrix loop(5, 2);
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * M_PI * i / 5, b = 2 * M_PI * ((2 * i) % 5) / 5;
    gon.row(i) << std::cos(a), std::sin(a);
    star.row(i) << std::cos(b), std::sin(b);
    loop.row(i) << i, (i + 1) % 5;
  }
  EXPECT_TRUE(self_intersections(gon, loop).empty());
  EXPECT_FALSE(self_intersections(star, loop).empty());
}

TEST(SelfIntersection, ATolerancePassesRoundingButNotCrossings) {
  // Two triangles of a closed shape's worth (only the pair matters): one pierces the other by
  // `depth` along z.
  auto pierced = [](double depth) {
    PointMatrix V(6, 3);
    V << 0, 0, 0, 2, 0, 0, 0, 2, 0,  // in z = 0
        0.5, 0.5, -depth, 0.6, 0.5, 1, 0.5, 0.6, 1;  // one corner below it
    SimplexMatrix F(2, 3);
    F << 0, 1, 2, 3, 4, 5;
    return std::make_pair(V, F);
  };
  const auto [shallow, shallow_faces] = pierced(1e-13);
  EXPECT_EQ(self_intersections(shallow, shallow_faces, 0).size(), 1u);        // the exact test finds it
  EXPECT_TRUE(self_intersections(shallow, shallow_faces, 0, 1e-9).empty());  // rounding: left out
  const auto [deep, deep_faces] = pierced(0.1);
  EXPECT_EQ(self_intersections(deep, deep_faces, 0, 1e-9).size(), 1u);
  // Two triangles in one plane overlapping over a wide region: a fold, whatever the tolerance.
  PointMatrix V(6, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0, 2.5, 0.5, 0, 0.5, 2.5, 0;
  SimplexMatrix F(2, 3);
  F << 0, 1, 2, 3, 4, 5;
  EXPECT_EQ(self_intersections(V, F, 0, 1e-9).size(), 1u);
  // ... and barely overlapping (a sliver 1e-13 wide): rounding.
  V.row(3) << 1 - 1e-13, 1 - 1e-13, 0;
  V.row(4) << 3, 0, 0;
  V.row(5) << 0, 3, 0;
  EXPECT_EQ(self_intersections(V, F, 0).size(), 1u);
  EXPECT_TRUE(self_intersections(V, F, 0, 1e-9).empty());
}

TEST(MorphSkeleton, SplitsAtGivenPointsSkipUnsafeOnesAndTellTheirParents) {
  PointMatrix P = two_planes(20, 3);
  SimplexMatrix A = delaunay_exact(P).simplices;
  const double before = total_volume(P, A);
  // An edge of the fill, split at its exact midpoint (a given position).
  const std::vector<Index> edge{A(0, 0), A(0, 1)};
  PointMatrix at(1, 4);
  at.row(0) = 0.5 * (P.row(edge[0]) + P.row(edge[1]));
  std::vector<Index> parents;
  SplitOptions how;
  how.positions = &at;
  how.parents = &parents;
  const Index rows = static_cast<Index>(A.rows());
  const IndexVector added = split_faces(P, A, {edge}, how);
  ASSERT_EQ(added.size(), 1);
  EXPECT_EQ((P.row(added(0)) - at.row(0)).norm(), 0.0);
  EXPECT_GT(signed_volumes(P, A).minCoeff(), 0.0);
  EXPECT_NEAR(total_volume(P, A), before, 1e-9 * before);
  ASSERT_EQ(parents.size(), static_cast<size_t>(A.rows()));
  for (Index r = 0; r < rows; ++r) EXPECT_EQ(parents[r], r);
  for (Index r = rows; r < A.rows(); ++r) {  // each new simplex comes from one that held the edge
    const auto parent = A.row(parents[r]);
    EXPECT_TRUE(std::find(parent.data(), parent.data() + 5, added(0)) != parent.data() + 5);
  }
  // A split that would leave a simplex thinner than asked for is skipped: no point, -1.
  SplitOptions strict;
  strict.skip_unsafe = true;
  strict.thinnest = 1.0;  // no simplex is that fat
  const Index points = static_cast<Index>(P.rows());
  const SimplexMatrix kept = A;
  const IndexVector none = split_faces(P, A, {{A(1, 0), A(1, 1)}}, strict);
  EXPECT_EQ(none(0), -1);
  EXPECT_EQ(P.rows(), points);
  EXPECT_TRUE(A == kept);
}

TEST(DelaunayExact, TwoPlanesGiveNoFlatCellAndKeepEachPlanesTriangulation) {
  const PointMatrix P = two_planes(50, 3);
  const DelaunayTriangulation fill = delaunay_exact(P);
  EXPECT_EQ(fill.flat_simplices, 0);
  EXPECT_GT(signed_volumes(P, fill.simplices).minCoeff(), 0.0);
  const DelaunayTriangulation bottom = delaunay_exact(P.topLeftCorner(50, 3));
  EXPECT_EQ(missing_facets(fill.simplices, bottom.simplices).size(), 0);
}

TEST(MorphSkeleton, NudgedSteinerPointsKeepEveryRefinedFace) {
  // A 5 x 5 grid in z = 0 between two apexes: every unit square of it has
  // cocircular corners, so which diagonal is a Delaunay face is a tie that
  // only the exact predicate on these coordinates settles. Its triangulation
  // as the Delaunay triangulation has it stands for a refined facet whose
  // grid points are Steiner points; a nudge off the plane settles many ties
  // the other way.
  PointMatrix P(27, 3);
  P.row(0) << 2, 2, 3;
  P.row(1) << 2, 2, -3;
  for (int i = 0; i < 25; ++i) P.row(2 + i) << i % 5, i / 5, 0;
  const SimplexMatrix tets = delaunay_exact(P).simplices;
  std::set<std::array<Index, 3>> grid_faces;
  for (Index t = 0; t < tets.rows(); ++t)
    for (int drop = 0; drop < 4; ++drop) {
      std::array<Index, 3> face;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != drop) face[j++] = tets(t, k);
      std::sort(face.begin(), face.end());
      if (face[0] >= 2) grid_faces.insert(face);
    }
  ASSERT_EQ(grid_faces.size(), 32u);  // 16 squares, one diagonal each
  ConformingDelaunay c;
  c.points = P;
  c.constraints.resize(32, 3);
  Index row = 0;
  for (const auto& face : grid_faces) c.constraints.row(row++) << face[0], face[1], face[2];
  Index unnudged = 0;
  const PointMatrix nudged = nudged_steiner_points(c, 2, 1e-3, unnudged);
  EXPECT_EQ(missing_facets(delaunay_exact(nudged).simplices, c.constraints).size(), 0);
  EXPECT_EQ(nudged.topRows(2), P.topRows(2));
  EXPECT_LE((nudged - P).cwiseAbs().maxCoeff(), 1e-3);
  Index moved = 0;
  for (Index v = 2; v < 27; ++v) moved += nudged.row(v) != P.row(v);
  EXPECT_EQ(moved + unnudged, 25);
  EXPECT_GT(moved, 0);
  EXPECT_GT(unnudged, 0) << "no tie was at stake";
}
}  // namespace
}  // namespace animanifold
