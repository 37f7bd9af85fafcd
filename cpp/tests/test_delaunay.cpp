// Delaunay triangulations (delaunay.hpp): the conforming tetrahedralization,
// mended where TetGen leaves a face non-Delaunay, and the exact fill of a
// morph's two planes.
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "animanifold/errors.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <string>

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

// The fuzzed octahedron of tests/test_morph.py: its faces at the edge
// between vertices 3 and 4 fold onto each other at 0.0072°. Points the
// mending adds on one face encroach on the other, each round doubles the
// surface, and the mending stops at its bound on growth, long before its cap
// on rounds, naming the fold. A fold alone is no reason: a flat tetrahedron
// whose faces meet at 0.009° is its own Delaunay tetrahedralization.
TEST(ConformingDelaunay3d, StopsWhereTheMendingCascadesOnAThinFoldOnly) {
  PointMatrix P(6, 3);
  P << 1.41119643800418, 0.8706035671577572, 0.5491393530247684,  //
      -1.7048372180974551, -0.7137254901960783, -0.8235277362898283,  //
      -1.4404688746242968, 2.286274510333704, 1.708899096625336,  //
      -1.9999999999987632, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0;
  SimplexMatrix F(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  std::string message = "(no MeshingError)";
  try {
    conforming_delaunay_3d(P, F);
  } catch (const MeshingError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("the mending cascades ("), std::string::npos) << message;
  EXPECT_NE(message.find("the edge between vertices 3 and 4, which meet there at 0.0072 degrees"), std::string::npos)
      << message;

  PointMatrix flat(4, 3);
  flat << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, -0.4, 1e-4;
  SimplexMatrix faces(4, 3);
  faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  const ConformingDelaunay c = conforming_delaunay_3d(flat, faces);
  EXPECT_TRUE(c.is_delaunay);
  EXPECT_EQ(c.mending_rounds, 0);
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
