// The estimates of memory_estimates.hpp: what they count, and how they grow.
#include "animanifold/memory_estimates.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

using namespace animanifold;
using fixtures::octahedron_animation;

TEST(MemoryEstimates, StitchCountsItsPointsAndSimplices) {
  StitchInput in = octahedron_animation();  // 3 keyframes of 6 vertices and 8 faces
  const MemoryEstimate e = stitch_memory(in);
  EXPECT_EQ(e.doing, "stitching 3 keyframes of 6 vertices and 8 faces (48 simplices)");
  const double output = 18 * 4 * sizeof(double) + 48 * 4 * sizeof(Index);
  EXPECT_GE(e.bytes, output);
  EXPECT_LE(e.bytes, 4 * output);
  in.vertex_attributes["uv"] = PointMatrix::Zero(6, 2);
  EXPECT_GT(stitch_memory(in).bytes, e.bytes);
  // Inputs stitch() refuses (no keyframes) are estimated, not divided by zero.
  in.times.resize(0);
  EXPECT_EQ(stitch_memory(in).bytes, 0);
}

TEST(MemoryEstimates, EachLevelOfSubdivisionMultipliesTheEstimateByAboutEight) {
  const Complex manifold = stitch(octahedron_animation());
  const double one = manifold_subdivision_memory(manifold, 1).bytes;
  const double three = manifold_subdivision_memory(manifold, 3).bytes;
  EXPECT_NEAR(three / one, 64, 16);
  EXPECT_EQ(manifold_subdivision_memory(manifold, 3).doing, "subdividing 48 simplices 3 times (24576 simplices)");
  // Frames: four faces per face and level (two segments per segment).
  EXPECT_NEAR(frame_subdivision_memory(100, 200, 3, 0, 4).bytes / frame_subdivision_memory(100, 200, 3, 0, 2).bytes,
              16, 2);
  EXPECT_NEAR(frame_subdivision_memory(100, 100, 2, 0, 4).bytes / frame_subdivision_memory(100, 100, 2, 0, 2).bytes,
              4, 1);
  EXPECT_GT(frame_subdivision_memory(0, 1, 3, 0, 1000).bytes, 1e300);  // no overflow to a small number
}

TEST(MemoryEstimates, RefinementCountsTheSimplicesAroundEachSplitFace) {
  // Two triangles sharing edge (1, 2): splitting it cuts both; splitting vertex 0 cuts none.
  Complex c;
  c.V = PointMatrix::Zero(4, 2);
  c.S.resize(2, 3);
  c.S << 0, 1, 2, 2, 1, 3;
  SimplexMatrix edge(1, 2), vertex(1, 2), hostile(1, 2);
  edge << 1, 2;
  vertex << 0, -1;
  hostile << 99, -7;  // out of range: refine() names it; the estimate skips it
  const double base = refinement_memory(c, SimplexMatrix(0, 2)).bytes;
  EXPECT_GT(refinement_memory(c, edge).bytes, refinement_memory(c, vertex).bytes);
  EXPECT_GT(refinement_memory(c, vertex).bytes, base);
  EXPECT_EQ(refinement_memory(c, edge).doing, "refining 2 simplices with 1 splits (about 4 simplices)");
  EXPECT_NO_THROW(refinement_memory(c, hostile));
}
