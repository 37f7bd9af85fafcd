// Slicing a manifold (slice.hpp): slice(), the interval index, and Slicer
// with its interval frames (a frame, its topology interval and rates).
#include "animanifold/errors.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/stitch.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "fixtures.hpp"

using namespace animanifold;
using fixtures::octahedron_animation;

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
    // A vertex's coordinate and the doubles either side of it: the index keeps
    // float bounds, so only the exact recheck tells these apart.
    const double x = V(17, axis), below = std::nextafter(x, -1e300), above = std::nextafter(x, 1e300);
    for (double value : {-6.0, -2.5, 0.0, 1.0, 4.9, 6.0, x, below, above}) {
      std::vector<Index> hits;
      index.stab(V, S, value, hits);
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

// stab() reports hits by lowest coordinate, then by simplex: with ties,
// negative coordinates, and -0 tying with +0 as they compare.
TEST(Slice, IntervalIndexReportsHitsByLowThenSimplex) {
  std::mt19937 rng(11);
  const double lows[] = {-3.5, -0.0, 0.0, 2.25, -1e-300, 1e-300, -3.5, 7.0};
  std::uniform_int_distribution<int> pick(0, 7);
  const Index count = 300;
  PointMatrix V(2 * count, 1);
  SimplexMatrix S(count, 2);
  for (Index s = 0; s < count; ++s) {
    V(2 * s, 0) = lows[pick(rng)], V(2 * s + 1, 0) = 10.0;  // every simplex holds 8
    S.row(s) << 2 * s + 1, 2 * s;
  }
  const IntervalIndex index(V, S, 0);
  std::vector<Index> hits;
  index.stab(V, S, 8.0, hits);
  std::vector<Index> expected(count);
  std::iota(expected.begin(), expected.end(), 0);
  std::stable_sort(expected.begin(), expected.end(), [&](Index a, Index b) { return V(2 * a, 0) < V(2 * b, 0); });
  EXPECT_EQ(hits, expected);
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

// The interval-frame tests animate the octahedron otherwise (moving between
// the first two keyframes, with a vertex attribute): their own namespace
// keeps their octahedron_animation from the one above.
namespace interval_frames {

namespace {

// The octahedron through keyframes at 0, 0.4 and 1.5, growing then moving,
// with a per-keyframe vertex attribute that changes between them.
std::shared_ptr<const Complex> octahedron_animation() {
  Eigen::Matrix3d offset;
  offset << 0, 0, 0, 0.2, 0, 0, 1, 1, 0;
  StitchInput in = fixtures::octahedron_keyframes({0.0, 0.4, 1.5}, {1.0, 1.5, 1.0}, offset);
  PointMatrix weight(18, 2);
  for (Index r = 0; r < 18; ++r) weight.row(r) << r, 0.5 * r * r;
  in.vertex_attributes["weight"] = weight;
  return std::make_shared<const Complex>(stitch(in));
}

std::set<std::pair<Index, Index>> cut_edges(const Slice& s) {
  std::set<std::pair<Index, Index>> edges;
  for (Index p = 0; p < s.vertex_edges.rows(); ++p) edges.insert({s.vertex_edges(p, 0), s.vertex_edges(p, 1)});
  return edges;
}

template <class Matrix>
bool same(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
}

}  // namespace

TEST(IntervalFrame, MovedVerticesAreTheSlicesInsideTheInterval) {
  const auto m = octahedron_animation();
  Slicer slicer(m);
  for (int axis : {3, 0}) {  // time, and a sweep view
    const double value = axis == 3 ? 0.9 : 0.1;
    const IntervalFrame frame = slicer.interval_frame(axis, value);
    ASSERT_LT(frame.lo, value);
    ASSERT_GT(frame.hi, value);
    for (double w : {0.01, 0.3, 0.5, 0.99}) {
      const double at = frame.lo + w * (frame.hi - frame.lo);
      const Slice fresh = slicer.slice(axis, at);  // indexed, as the frame: same face order
      ASSERT_TRUE(same(fresh.faces, frame.slice.faces)) << "axis " << axis << " at " << at;
      ASSERT_TRUE(same(fresh.vertex_edges, frame.slice.vertex_edges)) << "axis " << axis << " at " << at;
      const double dt = at - value;
      EXPECT_LT((frame.slice.vertices + dt * frame.rate - fresh.vertices).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((frame.slice.edge_parameter + dt * frame.parameter_rate - fresh.edge_parameter).cwiseAbs().maxCoeff(),
                1e-12);
      const PointMatrix& weight = frame.slice.vertex_attributes.at("weight");
      EXPECT_LT((weight + dt * frame.attribute_rates.at("weight") - fresh.vertex_attributes.at("weight"))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-10);
    }
  }
}

TEST(Slice, AShapeSliceIsTheSliceWithoutNormalsOrAttributes) {
  auto m = octahedron_animation();
  Complex with_face_data = *m;
  SimplexMatrix material(with_face_data.S.rows(), 1);
  for (Index s = 0; s < material.rows(); ++s) material(s, 0) = s % 3;
  with_face_data.simplex_attributes["material"] = material;
  m = std::make_shared<const Complex>(std::move(with_face_data));
  Slicer slicer(m);
  for (int axis : {3, 0}) {  // time, and a sweep view (its faces turned over)
    for (double value : {0.0, 0.2, 0.4, 0.9, 1.5}) {
      if (axis == 0 && value > 0.5) continue;
      // Through the index and without it (a scan): their face orders differ.
      const std::pair<Slice, Slice> pairs[] = {{slice(*m, axis, value), slice_shape(*m, axis, value)},
                                               {slicer.slice(axis, value), slicer.slice_shape(axis, value)}};
      for (const auto& [full, shape] : pairs) {
        ASSERT_GT(full.faces.rows(), 0) << "axis " << axis << " at " << value;
        ASSERT_GT(full.normals.rows(), 0);
        ASSERT_FALSE(full.vertex_attributes.empty());
        ASSERT_FALSE(full.face_attributes.empty());
        EXPECT_TRUE(same(shape.vertices, full.vertices)) << "axis " << axis << " at " << value;
        EXPECT_TRUE(same(shape.faces, full.faces)) << "axis " << axis << " at " << value;
        EXPECT_TRUE(same(shape.vertex_edges, full.vertex_edges)) << "axis " << axis << " at " << value;
        EXPECT_TRUE(same(shape.edge_parameter, full.edge_parameter)) << "axis " << axis << " at " << value;
        EXPECT_TRUE(same(shape.face_simplex, full.face_simplex)) << "axis " << axis << " at " << value;
        EXPECT_EQ(shape.normals.rows(), 0);
        EXPECT_TRUE(shape.vertex_attributes.empty());
        EXPECT_TRUE(shape.face_attributes.empty());
      }
    }
  }
}

TEST(IntervalFrame, TheIntervalEndsWhereTheFacesChange) {
  const auto m = octahedron_animation();
  Slicer slicer(m);
  const IntervalFrame frame = slicer.interval_frame(3, 0.9);
  EXPECT_EQ(frame.lo, 0.4);  // the keyframes on either side
  EXPECT_EQ(frame.hi, 1.5);
  const auto inside = cut_edges(frame.slice);
  EXPECT_EQ(cut_edges(slice(*m, 3, 0.4 + 1e-9)), inside);
  EXPECT_EQ(cut_edges(slice(*m, 3, 1.5 - 1e-9)), inside);
  EXPECT_NE(cut_edges(slice(*m, 3, 0.4)), inside);
  EXPECT_NE(cut_edges(slice(*m, 3, 0.4 - 1e-9)), inside);
  // A sweep view: every vertex coordinate along x bounds an interval.
  std::set<double> xs(m->V.col(0).begin(), m->V.col(0).end());
  const IntervalFrame sweep = slicer.interval_frame(0, 0.1);
  const auto above = xs.upper_bound(0.1);
  EXPECT_EQ(sweep.hi, *above);
  EXPECT_EQ(sweep.lo, *std::prev(above));
  EXPECT_NE(cut_edges(slice(*m, 0, sweep.hi + 1e-9)), cut_edges(sweep.slice));
  EXPECT_NE(cut_edges(slice(*m, 0, sweep.lo - 1e-9)), cut_edges(sweep.slice));
}

TEST(IntervalFrame, NoIntervalOnAVertexCoordinateOrOutside) {
  Slicer slicer(octahedron_animation());
  for (double value : {0.4, 0.0, 1.5, -0.1, 2.0, 0.4 + 1e-15}) {
    EXPECT_FALSE(slicer.index(3).topology_interval(value)) << value;
    EXPECT_THROW(slicer.interval_frame(3, value), InputError) << value;
  }
  EXPECT_THROW(slicer.interval_frame(4, 0.9), InputError);
  EXPECT_THROW(slicer.interval_frame(3, std::nan("")), InputError);
}

TEST(Slicer, ThreadsTakingTheFirstSlicesAtOnceGetTheSerialSlices) {
  const auto m = octahedron_animation();
  const std::vector<double> values = {0.1, 0.5, 0.9, 1.2};
  Slicer serial_slicer(m);
  std::vector<Slice> serial;
  for (double v : values) serial.push_back(serial_slicer.slice(3, v));
  for (int round = 0; round < 20; ++round) {
    Slicer slicer(m);  // fresh: no index yet
    std::vector<Slice> got(values.size());
    std::vector<std::thread> threads;
    for (size_t i = 0; i < values.size(); ++i)
      threads.emplace_back([&, i] { got[i] = slicer.slice(3, values[i]); });
    for (auto& t : threads) t.join();
    for (size_t i = 0; i < values.size(); ++i) {
      ASSERT_TRUE(same(got[i].faces, serial[i].faces)) << "round " << round << " value " << values[i];
      ASSERT_TRUE(same(got[i].vertices, serial[i].vertices)) << "round " << round << " value " << values[i];
    }
  }
}

}  // namespace interval_frames

TEST(Slice, TheSnapToleranceOfAnExtremeManifoldIsFinite) {
  // Times at -1e308 and 1e308: their difference overflows, and a tolerance
  // computed from it would take every value for a vertex's.
  Complex m = stitch(octahedron_animation());
  for (Index v = 0; v < m.V.rows(); ++v)
    if (m.V(v, 3) != 0.4) m.V(v, 3) = m.V(v, 3) == 0.0 ? -1e308 : 1e308;
  const IntervalIndex index(m.V, m.S, 3);
  const auto interval = index.topology_interval(5e307);
  ASSERT_TRUE(interval.has_value());
  EXPECT_EQ(interval->first, 0.4);
  EXPECT_EQ(interval->second, 1e308);
}

TEST(IntervalIndex, TakesTwelveBytesASimplexAndEightADistinctVertexCoordinate) {
  const Complex m = stitch(octahedron_animation());
  const IntervalIndex index(m.V, m.S, 3);
  std::set<double> times(m.V.col(3).begin(), m.V.col(3).end());
  EXPECT_EQ(index.memory_bytes(), 12 * static_cast<size_t>(m.S.rows()) + 8 * times.size());
}

TEST(IntervalIndex, RefusesToStabAnotherManifold) {
  const Complex m = stitch(octahedron_animation());
  const IntervalIndex index(m.V, m.S, 3);
  std::vector<Index> hits;
  const SimplexMatrix fewer = m.S.topRows(m.S.rows() - 1);
  EXPECT_THROW(index.stab(m.V, fewer, 0.5, hits), InputError);
  EXPECT_TRUE(hits.empty());
}
