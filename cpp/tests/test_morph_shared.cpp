// Position-keyed perturbation (perturbation.hpp) and the prisms of a fill
// over cells both planes share (morph_skeleton.hpp: shared_prisms), and
// shelling slivers off a boundary (shelling.hpp).
#include "animanifold/complex.hpp"
#include "animanifold/delaunay.hpp"
#include "morph_skeleton.hpp"
#include "animanifold/perturbation.hpp"
#include "animanifold/shelling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>

namespace animanifold {
namespace {

TEST(Perturbation, IsAFunctionOfPositionOnly) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  PointMatrix V(50, 3);
  for (Index r = 0; r < V.rows(); ++r) V.row(r) << g(rng), g(rng), g(rng);
  V.row(7) << 0.0, -0.0, 1.0;
  PointMatrix reversed = V.colwise().reverse();
  reversed.row(V.rows() - 1 - 7) << -0.0, 0.0, 1.0;  // -0.0 and 0.0 alike
  const PointMatrix a = perturbed_by_position(V, 1e-3, 42), b = perturbed_by_position(reversed, 1e-3, 42);
  for (Index r = 0; r < V.rows(); ++r) EXPECT_EQ(a.row(r), b.row(V.rows() - 1 - r)) << r;
  double largest = 0.0, mean = 0.0;
  for (Index r = 0; r < V.rows(); ++r)
    for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(a(r, c) - V(r, c))), mean += (a(r, c) - V(r, c));
  EXPECT_LE(largest, 1e-3);
  EXPECT_GT(largest, 5e-4);                 // spread over the range, not stuck near 0
  EXPECT_LT(std::abs(mean / 150), 2e-4);    // and centred
  EXPECT_NE(perturbed_by_position(V, 1e-3, 43), a);  // another salt, other offsets
  // Coordinates of one point get different offsets.
  EXPECT_NE(position_hash_offset(V.row(3).data(), 3, 0, 42), position_hash_offset(V.row(3).data(), 3, 1, 42));
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

}  // namespace
}  // namespace animanifold

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
