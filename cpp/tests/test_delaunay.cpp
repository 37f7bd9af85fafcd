// Delaunay triangulations (delaunay.hpp): the conforming tetrahedralization,
// mended where TetGen leaves a face non-Delaunay, and the exact fill of a
// morph's two planes.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>

#include "fixtures.hpp"

namespace animanifold {
namespace {

using fixtures::at;
using fixtures::normal;
using fixtures::two_planes;

// A flat tetrahedron: its big face (z = 0) has the apex just below its
// centre and a free point (a skeleton point, say) just above, both inside
// its circumsphere. No sphere through that face is empty, and TetGen's -D
// leaves it so (no Steiner point at all): the mending must mend it.
TEST(ConformingDelaunay3d, MendsTheFaceTetgenLeavesNonDelaunay) {
  PointMatrix P(5, 3);
  P << 0, 0, 0, 2, 0, 0, 1, 1.7, 0, 1, 0.6, -0.3, 1.02, 0.58, 0.3;
  SimplexMatrix F(4, 3);
  F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  const ConformingDelaunay c = conforming_delaunay_3d(P, F);
  ASSERT_TRUE(c.is_delaunay);
  EXPECT_EQ(c.non_delaunay_faces, 0);
  EXPECT_GE(c.mending_rounds, 1);
  EXPECT_GT(c.mended_points, 0);
  EXPECT_EQ(c.points.topRows(5), P);
  EXPECT_EQ(missing_facets(c.simplices, c.constraints).size(), 0);
  EXPECT_EQ(missing_facets(delaunay_exact(c.points).simplices, c.constraints).size(), 0);
  // The refined faces tile the input: on their parents, oriented like them, the same area.
  double area_in = 0, area_out = 0;
  for (Index f = 0; f < F.rows(); ++f) area_in += 0.5 * normal(P, {F(f, 0), F(f, 1), F(f, 2)}).norm();
  for (Index r = 0; r < c.constraints.rows(); ++r) {
    const std::array<Index, 3> t{c.constraints(r, 0), c.constraints(r, 1), c.constraints(r, 2)};
    const Index parent = c.constraint_parent(r);
    const std::array<Index, 3> p{F(parent, 0), F(parent, 1), F(parent, 2)};
    const Eigen::Vector3d n = normal(P, p).normalized();
    EXPECT_GT(normal(c.points, t).dot(n), 0);
    for (const Index v : t) EXPECT_NEAR((at(c.points, v) - at(P, p[0])).dot(n), 0.0, 1e-12);
    area_out += 0.5 * normal(c.points, t).norm();
  }
  EXPECT_NEAR(area_out, area_in, 1e-12 * area_in);
}

TEST(DelaunayExact, TwoPlanesGiveNoFlatCellAndKeepEachPlanesTriangulation) {
  const PointMatrix P = two_planes(50, 3);
  const DelaunayTriangulation fill = delaunay_exact(P);
  EXPECT_EQ(fill.flat_simplices, 0);
  EXPECT_GT(signed_volumes(P, fill.simplices).minCoeff(), 0.0);
  const DelaunayTriangulation bottom = delaunay_exact(P.topLeftCorner(50, 3));
  EXPECT_EQ(missing_facets(fill.simplices, bottom.simplices).size(), 0);
}

}  // namespace
}  // namespace animanifold
