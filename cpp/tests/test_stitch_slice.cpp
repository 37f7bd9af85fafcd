#include "animanifold/errors.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/stitch.hpp"

#include <gtest/gtest.h>

#include <random>

#include "fixtures.hpp"

using namespace animanifold;

namespace {

// A closed octahedron with outward faces, moved through three keyframes.
StitchInput octahedron_animation() {
  Eigen::Matrix3d offset;
  offset << 0, 0, 0, 0, 0, 0, 1, 1, 0;
  return fixtures::octahedron_keyframes({0.0, 0.4, 1.5}, {1.0, 1.5, 1.0}, offset);
}

}  // namespace

TEST(Stitch, CountsAndConformity) {
  const Complex m = stitch(octahedron_animation());
  EXPECT_EQ(m.S.rows(), 3 * 8 * 2);
  EXPECT_EQ(m.V.rows(), 18);
  const auto report = check_manifold(m.S);
  EXPECT_TRUE(report.is_oriented_manifold());
  EXPECT_EQ(report.boundary_facets, 16);
}

TEST(Stitch, ErrorsNameTheCulprit) {
  StitchInput in = octahedron_animation();
  in.times(2) = 0.4;
  try {
    stitch(in);
    FAIL() << "non-increasing times accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 2"), std::string::npos) << e.what();
  }
  in = octahedron_animation();
  in.frames(9, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(stitch(in), InputError);
}

TEST(Slice, KeyframesComeBackExactlyAtBothEnds) {
  const StitchInput in = octahedron_animation();
  const Complex m = stitch(in);
  for (int i = 0; i < 3; ++i) {
    const Slice s = slice(m, 3, in.times(i));
    ASSERT_EQ(s.faces.rows(), 8) << "keyframe " << i;
    ASSERT_EQ(s.vertices.rows(), 6) << "keyframe " << i;
    for (Index p = 0; p < s.vertices.rows(); ++p) {
      ASSERT_EQ(s.vertex_edges(p, 0), s.vertex_edges(p, 1));
      const Index id = s.vertex_edges(p, 0);
      EXPECT_EQ(id / 6, i);
      EXPECT_EQ((s.vertices.row(p) - in.frames.row(id)).norm(), 0.0);
    }
  }
}

TEST(Slice, AValueARoundingAwayFromAKeyframeGivesTheKeyframe) {
  // A frame's time computed as t0 + k·dt can land an ulp off a keyframe: cut a hair above it,
  // each edge out of a keyframe vertex gave a slice vertex of its own within an ulp of it, and
  // faces between them folded. Within 1e-12 of the extent, the slice is the keyframe's.
  const StitchInput in = octahedron_animation();
  const Complex m = stitch(in);
  for (int i = 0; i < 3; ++i)
    for (const double off : {std::nextafter(in.times(i), 1e9), std::nextafter(in.times(i), -1e9)}) {
      const Slice s = slice(m, 3, off);
      ASSERT_EQ(s.faces.rows(), 8) << "keyframe " << i << " at " << off;
      for (Index p = 0; p < s.vertices.rows(); ++p) {
        ASSERT_EQ(s.vertex_edges(p, 0), s.vertex_edges(p, 1));
        EXPECT_EQ(s.vertex_edges(p, 0) / 6, i);
      }
    }
  // Farther off, an in-between frame: interpolated, not a keyframe's vertices.
  const Slice between = slice(m, 3, in.times(1) + 1e-6 * (in.times(2) - in.times(0)));
  EXPECT_NE(between.vertex_edges(0, 0), between.vertex_edges(0, 1));
}

TEST(Slice, IntervalIndexFindsExactlyTheStabbedSimplices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5, 5);
  PointMatrix V(400, 4);
  for (Index r = 0; r < V.rows(); ++r)
    for (int c = 0; c < 4; ++c) V(r, c) = u(rng);
  SimplexMatrix S(100, 4);
  for (Index s = 0; s < 100; ++s)
    for (int c = 0; c < 4; ++c) S(s, c) = 4 * s + c;
  for (int axis = 0; axis < 4; ++axis) {
    IntervalIndex index(V, S, axis);
    for (double value : {-6.0, -2.5, 0.0, 1.0, 4.9, 6.0, V(17, axis)}) {
      std::vector<Index> hits;
      index.stab(value, hits);
      std::sort(hits.begin(), hits.end());
      std::vector<Index> expected;
      for (Index s = 0; s < S.rows(); ++s) {
        double lo = 1e300, hi = -1e300;
        for (int c = 0; c < 4; ++c) lo = std::min(lo, V(S(s, c), axis)), hi = std::max(hi, V(S(s, c), axis));
        if (lo <= value && value <= hi) expected.push_back(s);
      }
      EXPECT_EQ(hits, expected) << "axis " << axis << " value " << value;
    }
  }
}

TEST(Slice, InBetweenFrameIsWatertight) {
  const Complex m = stitch(octahedron_animation());
  const Slice s = slice(m, 3, 0.9);
  // every directed edge has its reverse exactly once
  std::map<std::pair<Index, Index>, int> directed;
  for (Index f = 0; f < s.faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) ++directed[{s.faces(f, c), s.faces(f, (c + 1) % 3)}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "hole at " << edge.first << "-" << edge.second;
  }
}
