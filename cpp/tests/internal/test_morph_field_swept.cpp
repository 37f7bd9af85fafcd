// swept_when_same (morph_field.hpp): the field method sweeps a surface that
// is both source and target, whatever the order of its points and faces and
// the corner each face starts from; a face turned over, or a point moved, is
// another surface.
#include "morph_field.hpp"

#include "../fixtures.hpp"

#include <gtest/gtest.h>

using namespace animanifold;

namespace {

// The octahedron with its points in reverse order, each face from its second
// corner, the faces in reverse order: the same surface.
void listed_otherwise(const PointMatrix& V, const SimplexMatrix& F, PointMatrix& W, SimplexMatrix& G) {
  const Index n = V.rows();
  W = V.colwise().reverse();
  G.resize(F.rows(), 3);
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) G(F.rows() - 1 - f, c) = n - 1 - F(f, (c + 1) % 3);
}

}  // namespace

TEST(MorphFieldSwept, TheSameSurfaceListedOtherwiseIsSweptAndEachEndIsIt) {
  PointMatrix V, W;
  SimplexMatrix F, G;
  fixtures::octahedron(V, F);
  listed_otherwise(V, F, W, G);
  const std::optional<Complex> swept = swept_when_same(V, F, W, G, 1.0, 3.0);
  ASSERT_TRUE(swept.has_value());
  // Two copies of the points, at t0 then t1; three tets per face's prism.
  ASSERT_EQ(swept->V.rows(), 2 * V.rows());
  EXPECT_EQ(swept->S.rows(), 3 * F.rows());
  for (Index v = 0; v < V.rows(); ++v) {
    EXPECT_EQ(swept->V.row(v).head(3), V.row(v));
    EXPECT_EQ(swept->V(v, 3), 1.0);
    EXPECT_EQ(swept->V(V.rows() + v, 3), 3.0);
  }
}

TEST(MorphFieldSwept, AFaceTurnedOverOrAPointMovedIsAnotherSurface) {
  PointMatrix V, W;
  SimplexMatrix F, G;
  fixtures::octahedron(V, F);
  listed_otherwise(V, F, W, G);
  SimplexMatrix turned = G;
  std::swap(turned(0, 0), turned(0, 1));
  EXPECT_FALSE(swept_when_same(V, F, W, turned, 0.0, 1.0).has_value());
  PointMatrix moved = W;
  moved(2, 1) += 1e-12;
  EXPECT_FALSE(swept_when_same(V, F, moved, G, 0.0, 1.0).has_value());
  EXPECT_FALSE(swept_when_same(V, F, W.topRows(W.rows() - 1), G, 0.0, 1.0).has_value());
}
