// The pieces of the skeleton morph (morph_skeleton.hpp) on small known
// configurations: splitting faces of a fill, perturbing along hull faces,
// points on and depth in a hull, nudged Steiner points, the prisms of a fill
// over cells both planes share, and cap points over flat sides of a hull.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/perturbation.hpp"
#include "morph_skeleton.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include "../fixtures.hpp"

namespace animanifold {
namespace {

using fixtures::two_planes;

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

// A prism over a triangulated cube: the same points in two planes t = 0, 1
// (a fill where the inputs coincide) and one point more at t = 1 only.
TEST(SharedPrisms, PrismsOverSharedCellsAreFoundAndThoseOutsideBothMarked) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 40;
  PointMatrix P(2 * n + 1, 4);
  for (int r = 0; r < n; ++r) {
    P.row(r) << u(rng), u(rng), u(rng), 0.0;
    P.row(n + r) = P.row(r);
    P(n + r, 3) = 1.0;
  }
  P.row(2 * n) << 3.0, 3.0, 3.0, 1.0;  // only in the target's plane: the prisms near it are not shared
  const DelaunayTriangulation fill = delaunay_exact(P);
  std::vector<bool> in_source(P.rows(), false), in_target(P.rows(), false);
  for (int r = 0; r < n; ++r) in_source[r] = true;
  for (int r = n; r <= 2 * n; ++r) in_target[r] = true;
  // Every plane cell "outside" but those touching point 0 (a stand-in for a classification).
  auto plane = [&](const std::vector<bool>& in) {
    PlaneCells cells;
    std::vector<Index> rows;
    std::set<std::array<Index, 4>> seen;
    for (Index s = 0; s < fill.simplices.rows(); ++s) {
      std::array<Index, 4> k{};
      int count = 0;
      for (int c = 0; c < 5; ++c)
        if (in[fill.simplices(s, c)] && count < 4) k[count++] = fill.simplices(s, c);
      int total = 0;
      for (int c = 0; c < 5; ++c) total += in[fill.simplices(s, c)];
      if (total != 4) continue;
      std::sort(k.begin(), k.end());
      if (seen.insert(k).second) rows.insert(rows.end(), k.begin(), k.end());
    }
    cells.cells = Eigen::Map<SimplexMatrix>(rows.data(), static_cast<Index>(rows.size() / 4), 4);
    for (Index c = 0; c < cells.cells.rows(); ++c) {
      bool touches = false;
      for (int i = 0; i < 4; ++i) touches = touches || cells.cells(c, i) == 0 || cells.cells(c, i) == n;
      cells.outside.push_back(!touches);
      cells.flat.push_back(false);
    }
    return cells;
  };
  const std::vector<Prism> prism = shared_prisms(P, fill.simplices, in_source, in_target, plane(in_source), plane(in_target));
  Index inside = 0, outside = 0, other = 0;
  for (Index s = 0; s < fill.simplices.rows(); ++s) {
    // Which places (xyz) the simplex spans, and whether it touches the target-only point.
    std::set<Index> places;
    bool lone = false, corner0 = false;
    for (int c = 0; c < 5; ++c) {
      const Index v = fill.simplices(s, c);
      lone = lone || v == 2 * n;
      places.insert(v < n ? v : v - n);
      corner0 = corner0 || v == 0 || v == n;
    }
    if (lone || places.size() != 4) {
      EXPECT_EQ(prism[s], Prism::NotShared) << s;
      ++other;
    } else if (prism[s] == Prism::SharedOutside) {
      EXPECT_FALSE(corner0) << s;
      ++outside;
    } else {
      EXPECT_EQ(prism[s], Prism::SharedInside) << s;
      ++inside;
    }
  }
  EXPECT_GT(inside, 0);
  EXPECT_GT(outside, 0);
  EXPECT_GT(other, 0);
  // The degenerate prisms are triangulated with their own corners only: in the shared part
  // every simplex spans exactly the four columns of one cell.
  EXPECT_GT(signed_volumes(P, fill.simplices).minCoeff(), 0.0);
}

// A torus around z (radii 1 and 0.3, 24 x 12 quads split in two, outward):
// its hull's flat discs at z = ±0.3 lie over the hole.
void torus(PointMatrix& V, SimplexMatrix& F) {
  const int major = 24, minor = 12;
  V.resize(major * minor, 3);
  F.resize(2 * major * minor, 3);
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const double u = 2 * M_PI * i / major, w = 2 * M_PI * j / minor;
      V.row(i * minor + j) << (1 + 0.3 * std::cos(w)) * std::cos(u), (1 + 0.3 * std::cos(w)) * std::sin(u), 0.3 * std::sin(w);
    }
  int f = 0;
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const Index a = i * minor + j, b = ((i + 1) % major) * minor + j, c = ((i + 1) % major) * minor + (j + 1) % minor,
                  d = i * minor + (j + 1) % minor;
      F.row(f++) << a, b, c;
      F.row(f++) << a, c, d;
    }
}

TEST(HullCaps, OnePointOverEachDiscOfATorusBelowTheHullsOtherPlanes) {
  PointMatrix V;
  SimplexMatrix F;
  torus(V, F);
  const PointMatrix caps = hull_cap_points(V, F);
  ASSERT_EQ(caps.rows(), 2);
  const Index top = caps(0, 2) > 0 ? 0 : 1;
  for (const Index r : {top, 1 - top}) {
    EXPECT_NEAR(caps(r, 0), 0.0, 1e-6);  // over the disc's centre
    EXPECT_NEAR(caps(r, 1), 0.0, 1e-6);
    EXPECT_GT(std::abs(caps(r, 2)) - 0.3, 1e-2 * 2.6);  // outside the hull, not in a sliver with the disc
  }
  EXPECT_GT(caps(top, 2), 0.3);
  EXPECT_LT(caps(1 - top, 2), -0.3);
  // Below the plane of every face of the torus on its hull: the points see
  // only their discs, so their hull faces end at the discs' rims.
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    double highest = -1;
    for (Index v = 0; v < V.rows(); ++v) highest = std::max(highest, n.dot(Eigen::Vector3d(V.row(v).transpose()) - a));
    if (highest > 1e-12) continue;  // not a face on the hull
    for (Index r = 0; r < 2; ++r) EXPECT_LT(n.dot(Eigen::Vector3d(caps.row(r).transpose()) - a), 0.0) << "face " << f;
  }
}

TEST(HullCaps, NoneForConvexShapesOrFlatSidesOfTheShapeItself) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  EXPECT_EQ(hull_cap_points(V, F).rows(), 0);
  // A cube's squares are flat sides of its hull made of its own faces.
  PointMatrix C(8, 3);
  for (int i = 0; i < 8; ++i) C.row(i) << (i & 1 ? 1 : -1), (i & 2 ? 1 : -1), (i & 4 ? 1 : -1);
  SimplexMatrix Q(12, 3);
  Q << 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5;
  EXPECT_EQ(hull_cap_points(C, Q).rows(), 0);
}

TEST(HullCaps, TheSamePointsWhateverTheOrderOfThePoints) {
  // CGAL's hull triangulates a flat disc one way or another (by the order
  // of its points; under bpy, from one call to the next): the sums over its
  // triangles round differently, and a cap point one unit in the last place
  // off is perturbed quite otherwise (the same morph came out different).
  // The points are put on a grid, so none of that shows.
  PointMatrix V;
  SimplexMatrix F;
  torus(V, F);
  const PointMatrix first = hull_cap_points(V, F);
  const Index n = V.rows();
  PointMatrix reversed = V.colwise().reverse();
  SimplexMatrix renumbered = F;
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) renumbered(f, c) = n - 1 - F(f, c);
  const PointMatrix again = hull_cap_points(reversed, renumbered);
  ASSERT_EQ(first.rows(), 2);
  ASSERT_EQ(again.rows(), 2);
  const Index top = first(0, 2) > 0 ? 0 : 1, top_again = again(0, 2) > 0 ? 0 : 1;
  EXPECT_TRUE((first.row(top).array() == again.row(top_again).array()).all());
  EXPECT_TRUE((first.row(1 - top).array() == again.row(1 - top_again).array()).all());
}

}  // namespace
}  // namespace animanifold
