// Shelling slivers off a boundary (shelling.hpp).
#include "animanifold/shelling.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace animanifold {
namespace {

TEST(Shelling, TakesOffABoundarySliverButNeverPinches) {
  // A unit square of two triangles with a sliver triangle under its bottom edge.
  SimplexMatrix S(3, 3);
  S << 0, 1, 2,   // a b c
      0, 2, 3,    // a c d
      0, 4, 1;    // a e b: e just below ab
  const auto any = [](const Index*) { return true; };
  std::vector<bool> removed = shell_off(S, {2}, any);
  EXPECT_TRUE(removed[2]);
  EXPECT_FALSE(removed[0] || removed[1]);
  // A strip of four triangles p0 p1 p2 / q0 q1 q2: the second has only its top edge on the
  // boundary, and its opposite corner p1 lies on the bottom edge: removing it would leave a
  // bow tie at p1.
  SimplexMatrix strip(4, 3);
  strip << 0, 1, 3,  // p0 p1 q0
      1, 4, 3,       // p1 q1 q0
      1, 2, 4,       // p1 p2 q1
      2, 5, 4;       // p2 q2 q1
  removed = shell_off(strip, {1}, any);
  EXPECT_FALSE(removed[1]);
  // Facets refused by the predicate keep a candidate in.
  removed = shell_off(S, {2}, [](const Index* facet) { return facet[0] != 0; });
  EXPECT_FALSE(removed[2]);
}

}  // namespace
}  // namespace animanifold
