#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/normals.hpp"
#include "animanifold/threads.hpp"

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

namespace {

// The Kuhn triangulation of a side^3 grid of cubes: each cube cut into six
// tets along its main diagonal, all positively oriented, so the complex is a
// consistently oriented 3-manifold with a closed boundary.
SimplexMatrix kuhn_grid(int side) {
  const int n = side + 1;
  auto vertex = [n](int x, int y, int z) { return static_cast<Index>((z * n + y) * n + x); };
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const bool odd[6] = {false, true, true, false, false, true};
  SimplexMatrix S(side * side * side * 6, 4);
  Index row = 0;
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x)
        for (int p = 0; p < 6; ++p) {
          int corner[3] = {x, y, z};
          Index tet[4];
          tet[0] = vertex(corner[0], corner[1], corner[2]);
          for (int step = 0; step < 3; ++step) {
            ++corner[orders[p][step]];
            tet[step + 1] = vertex(corner[0], corner[1], corner[2]);
          }
          if (odd[p]) std::swap(tet[2], tet[3]);
          S.row(row++) << tet[0], tet[1], tet[2], tet[3];
        }
  return S;
}

}  // namespace

TEST(Complex, FacetChecksOfAGridAreRightAndTheSameOnAnyThreadCount) {
  const SimplexMatrix S = kuhn_grid(7);
  const int before = thread_count();
  set_thread_count(1);
  const ManifoldReport one = check_manifold(S);
  const FacetAdjacency adjacency_one = facet_adjacency(S);
  const SimplexMatrix boundary_one = boundary_facets(S);
  for (int count : {2, 3}) {
    set_thread_count(count);
    const ManifoldReport other = check_manifold(S);
    EXPECT_EQ(other.interior_facets, one.interior_facets);
    EXPECT_EQ(other.boundary_facets, one.boundary_facets);
    EXPECT_EQ(other.misoriented_facets, one.misoriented_facets);
    const FacetAdjacency adjacency = facet_adjacency(S);
    EXPECT_EQ(adjacency.neighbour, adjacency_one.neighbour);
    EXPECT_EQ(adjacency.opposite, adjacency_one.opposite);
    EXPECT_EQ(boundary_facets(S), boundary_one);
    SimplexMatrix from_the_check;  // the same boundary from check_manifold's own pass
    check_manifold(S, &from_the_check);
    EXPECT_EQ(from_the_check, boundary_one);
  }
  set_thread_count(before);
  EXPECT_TRUE(one.is_oriented_manifold());
  EXPECT_EQ(one.boundary_facets, 6 * 7 * 7 * 2);  // two triangles per boundary square
  EXPECT_EQ(one.interior_facets, (4 * S.rows() - one.boundary_facets) / 2);
  const ManifoldReport surface = check_manifold(boundary_one);
  EXPECT_TRUE(surface.is_oriented_manifold());
  EXPECT_EQ(surface.boundary_facets, 0);
  for (Index s = 0; s < S.rows(); ++s)
    for (int i = 0; i < 4; ++i) {
      const Index across = adjacency_one.neighbour(s, i);
      if (across >= 0) EXPECT_EQ(adjacency_one.neighbour(across, adjacency_one.opposite(s, i)), s);
    }
}

TEST(Complex, FacetChecksDoNotDependOnHowWidelyTheIndicesSpread) {
  // The same two tets with indices far apart (the records are then sorted
  // whole rather than bucketed by their smallest vertex).
  SimplexMatrix S(2, 4), spread(2, 4);
  S << 0, 1, 2, 3, 4, 2, 1, 3;
  for (Index s = 0; s < 2; ++s)
    for (int c = 0; c < 4; ++c) spread(s, c) = S(s, c) * 400000000 + 5;
  const ManifoldReport compact = check_manifold(S), wide = check_manifold(spread);
  EXPECT_TRUE(wide.is_oriented_manifold());
  EXPECT_EQ(wide.interior_facets, compact.interior_facets);
  EXPECT_EQ(wide.boundary_facets, compact.boundary_facets);
  EXPECT_EQ(facet_adjacency(spread).neighbour, facet_adjacency(S).neighbour);
  EXPECT_EQ(facet_adjacency(spread).opposite, facet_adjacency(S).opposite);
  SimplexMatrix boundary = boundary_facets(spread);
  for (Index r = 0; r < boundary.rows(); ++r)
    for (int c = 0; c < 3; ++c) boundary(r, c) = (boundary(r, c) - 5) / 400000000;
  EXPECT_EQ(boundary, boundary_facets(S));
}

TEST(Complex, AFacetInThreeSimplicesIsNamedOnAnyThreadCount) {
  // Three tets on the triangle (0, 1, 2), and a manifold grid far away in
  // the index range (the threads' ranges of buckets then differ).
  SimplexMatrix S = kuhn_grid(3);
  S.array() += 10;
  SimplexMatrix crowded(S.rows() + 3, 4);
  crowded << S, SimplexMatrix{{0, 1, 2, 3}, {1, 0, 2, 4}, {0, 1, 2, 5}};
  const int before = thread_count();
  for (int count : {1, 2, 3}) {
    set_thread_count(count);
    try {
      facet_adjacency(crowded);
      ADD_FAILURE() << "no error on " << count << " threads";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("facet (0, 1, ...)"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("is shared by 3 simplices"), std::string::npos) << e.what();
    }
    EXPECT_EQ(check_manifold(crowded).nonmanifold_facets, 1);
  }
  set_thread_count(before);
}
