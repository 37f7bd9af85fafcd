// The estimates of memory_estimates.hpp: what they count, and how they grow.
#include "animanifold/memory_estimates.hpp"

#include "animanifold/refine.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <optional>

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

namespace {

// A limit for one test, back to the default after it whatever happens.
struct ScopedLimit {
  explicit ScopedLimit(std::uint64_t bytes) { set_memory_limit(bytes); }
  ~ScopedLimit() { set_memory_limit(std::nullopt); }
};

}  // namespace

// The core calls check their own estimate, so a C++ caller is held to the limit as Python is.
TEST(MemoryEstimates, EveryEstimatedCoreCallRefusesBeyondTheLimitBeforeItAllocates) {
  const StitchInput in = octahedron_animation();
  const Complex manifold = stitch(in);
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  SimplexMatrix segments(2, 2);
  segments << 0, 1, 1, 2;
  const SimplexMatrix split_vertices = manifold.S.topRows(1).leftCols(2);
  const PointMatrix split_barycentric = PointMatrix::Constant(1, 2, 0.5);
  FrameSubdivisionOptions frame;
  frame.levels = 2;
  ManifoldSubdivisionOptions levels;
  levels.levels = 2;
  Slice slice;
  slice.vertices = V;
  slice.faces = F;

  const ScopedLimit limit(100);  // bytes: less than any of these calls needs
  EXPECT_THROW(stitch(in), MemoryLimitError);
  EXPECT_THROW(refine(manifold, split_vertices, split_barycentric), MemoryLimitError);
  EXPECT_THROW(subdivide_manifold(manifold, levels), MemoryLimitError);
  EXPECT_THROW(subdivide_frame(V, F, frame), MemoryLimitError);
  EXPECT_THROW(subdivide_polyline(V.leftCols(2), segments, frame), MemoryLimitError);
  EXPECT_THROW(smooth_slice(slice, frame), MemoryLimitError);
  set_memory_limit(std::uint64_t{1} << 30);
  EXPECT_NO_THROW(stitch(in));
  EXPECT_NO_THROW(subdivide_frame(V, F, frame));
}
