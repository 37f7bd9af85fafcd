#include "animanifold/complex.hpp"
#include "animanifold/errors.hpp"
#include "animanifold/hole_space.hpp"

#include <gtest/gtest.h>

#include "fixtures.hpp"

using namespace animanifold;

namespace {

// The octahedron with its top vertex pushed down to z = -0.5: a pyramid over
// the diamond |x| + |y| <= 1 (apex z = -1, volume 2/3) with a pit (apex
// z = -0.5, volume 1/3) taken out of it. Its convex hull is the pyramid, its
// hole space the pit.
void dented_octahedron(PointMatrix& V, SimplexMatrix& F) {
  fixtures::octahedron(V, F);
  V(4, 2) = -0.5;
}

bool closed_oriented(const SimplexMatrix& F) {
  const ManifoldReport r = check_manifold(F);
  return r.boundary_facets == 0 && r.is_oriented_manifold();
}

}  // namespace

TEST(HoleSpace, PitOfADentedOctahedron) {
  PointMatrix V;
  SimplexMatrix F;
  dented_octahedron(V, F);
  EXPECT_NEAR(solid_measure(V, F), 1.0 / 3.0, 1e-15);
  const Solid H = hole_space(V, F);
  ASSERT_FALSE(H.empty());
  EXPECT_TRUE(closed_oriented(H.faces));
  EXPECT_NEAR(solid_measure(H.vertices, H.faces), 1.0 / 3.0, 1e-15);  // the pit, outward
  for (Index v = 0; v < H.vertices.rows(); ++v) EXPECT_LE(H.vertices(v, 2), 1e-15);
}

TEST(HoleSpace, ConvexShapeHasNone) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  const Solid H = hole_space(V, F);
  EXPECT_TRUE(H.empty());
  EXPECT_EQ(H.vertices.cols(), 3);
}

TEST(HoleSpace, CShapeIn2D) {
  PointMatrix V(8, 2);  // [0, 3]^2 less the notch [1, 3] x [1, 2]
  V << 0, 0, 3, 0, 3, 1, 1, 1, 1, 2, 3, 2, 3, 3, 0, 3;
  SimplexMatrix F(8, 2);
  for (Index i = 0; i < 8; ++i) F.row(i) << i, (i + 1) % 8;
  const Solid H = hole_space(V, F);
  ASSERT_EQ(H.faces.rows(), 4);
  EXPECT_DOUBLE_EQ(solid_measure(H.vertices, H.faces), 2.0);
  // The frame [0, 3]^2 less H is the C shape again.
  PointMatrix square(4, 2);
  square << 0, 0, 3, 0, 3, 3, 0, 3;
  SimplexMatrix loop(4, 2);
  loop << 0, 1, 1, 2, 2, 3, 3, 0;
  const Subtraction cut = subtract_solid(square, loop, H.vertices, H.faces);
  EXPECT_FALSE(cut.unchanged);
  EXPECT_DOUBLE_EQ(solid_measure(cut.solid.vertices, cut.solid.faces), 7.0);
}

TEST(HoleSpace, SubtractKeepsAFrameTheHoleCannotTouch) {
  PointMatrix V, H;
  SimplexMatrix F, HF;
  dented_octahedron(H, HF);
  const Solid pit = hole_space(H, HF);
  fixtures::octahedron(V, F);
  V.col(0).array() += 5.0;  // far away: the bounding boxes do not overlap
  const Subtraction far = subtract_solid(V, F, pit.vertices, pit.faces);
  EXPECT_TRUE(far.unchanged);
  EXPECT_EQ(far.solid.vertices, V);
  EXPECT_EQ(far.solid.faces, F);
  fixtures::octahedron(V, F);
  V = V * 0.1;
  V.rowwise() += Eigen::RowVector3d(0.7, 0.7, -0.1);  // in the pit's bounding box, beside the pit
  const Subtraction beside = subtract_solid(V, F, pit.vertices, pit.faces);
  EXPECT_TRUE(beside.unchanged);
  fixtures::octahedron(V, F);
  V = V * 0.15;
  V.col(2).array() -= 0.3;  // inside the pit, which swallows it
  const Subtraction swallowed = subtract_solid(V, F, pit.vertices, pit.faces);
  EXPECT_FALSE(swallowed.unchanged);
  EXPECT_TRUE(swallowed.solid.empty());
}

TEST(HoleSpace, OpenOrMalformedInputsThrowNamingTheProblem) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  const SimplexMatrix open = F.topRows(7);
  EXPECT_THROW(
      {
        try {
          hole_space(V, open);
        } catch (const BooleanError& e) {
          EXPECT_STREQ(e.what(), "the shape is not closed (3 boundary edges)");
          throw;
        }
      },
      BooleanError);
  SimplexMatrix bad = F;
  bad(2, 1) = 9;
  EXPECT_THROW(hole_space(V, bad), InputError);
  EXPECT_THROW(intersect_solids(V, F, V.leftCols(2), F.leftCols(2)), InputError);
}

TEST(HoleSpace, SelfIntersectionTest) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  EXPECT_FALSE(intersects_itself(V, F));
  PointMatrix two(12, 3);
  two << V, V.rowwise() + Eigen::RowVector3d(0.5, 0, 0);
  SimplexMatrix both(16, 3);
  both << F, F.array() + 6;
  EXPECT_TRUE(intersects_itself(two, both));
}
