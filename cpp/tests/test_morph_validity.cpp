// check_frames (morph_validity.hpp) with work run beside the frames: the
// work runs once on any thread count, the frame checks report what they
// report without it, and what the work throws reaches the caller; crossings
// are checked on the spread frames asked for, and on the rest when asked
// once the work is done; frames asked for closer together find what falls
// between the spread ones.
#include "animanifold/morph.hpp"
#include "animanifold/morph_validity.hpp"
#include "animanifold/stitch.hpp"
#include "animanifold/threads.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <stdexcept>
#include <tuple>

using namespace animanifold;

namespace {

struct Inputs {
  PointMatrix VS, VT;
  SimplexMatrix FS, FT;
  Morph morph;
};

// A field morph of an octahedron into one twice its size.
Inputs growing_octahedron() {
  Inputs in;
  fixtures::octahedron(in.VS, in.FS);
  in.VT = 2.0 * in.VS, in.FT = in.FS;
  MorphOptions options;
  options.method = MorphMethod::Field;
  options.field_resolution = 6;
  options.field_layers = 5;
  in.morph = morph(in.VS, in.FS, in.VT, in.FT, options);
  return in;
}

MorphReport frames_checked(const Inputs& in, const std::function<void()>& alongside = {}) {
  MorphReport report;
  std::vector<std::function<void()>> work;
  if (alongside) work.push_back(alongside);
  check_frames(in.morph.manifold, 0.0, 1.0, in.VS, in.FS, in.VT, in.FT, report, work);
  return report;
}

// Restores the thread setting a test changes.
struct ThreadSetting {
  int before = thread_count();
  ~ThreadSetting() { set_thread_count(before); }
};

}  // namespace

TEST(MorphValidity, WorkBesideTheFramesRunsOnceAndLeavesTheirChecksAsTheyAre) {
  const Inputs in = growing_octahedron();
  const ThreadSetting restore;
  for (const int threads : {1, 2}) {
    set_thread_count(threads);
    const MorphReport alone = frames_checked(in);
    std::atomic<int> runs{0};
    const MorphReport beside = frames_checked(in, [&] { ++runs; });
    EXPECT_EQ(runs.load(), 1) << threads << " threads";
    EXPECT_GE(beside.frames_checked, 24);
    EXPECT_EQ(beside.frames_checked, alone.frames_checked);
    EXPECT_EQ(beside.noise_frames, alone.noise_frames);
    EXPECT_EQ(beside.crossing_frames, alone.crossing_frames);
    EXPECT_EQ(beside.topology_changes, alone.topology_changes);
  }
}

TEST(MorphValidity, WhatTheWorkBesideTheFramesThrowsReachesTheCaller) {
  const Inputs in = growing_octahedron();
  const ThreadSetting restore;
  for (const int threads : {1, 2}) {
    set_thread_count(threads);
    EXPECT_THROW(frames_checked(in, [] { throw std::runtime_error("the simplex checks failed"); }), std::runtime_error)
        << threads << " threads";
  }
}

TEST(MorphValidity, CrossingsAreCheckedOnTheFramesAskedAndOnTheRestWhenAskedAfterTheWork) {
  const Inputs in = growing_octahedron();
  for (const bool rest : {false, true}) {
    MorphReport report;
    bool work_done = false, asked_after_work = false;
    check_frames(in.morph.manifold, 0.0, 1.0, in.VS, in.FS, in.VT, in.FT, report, {[&] { work_done = true; }}, 1,
                 [&] {
                   asked_after_work = work_done;
                   return rest;
                 });
    EXPECT_TRUE(asked_after_work);
    EXPECT_EQ(report.crossing_frames_checked, rest ? 24 : 1);
    EXPECT_GE(report.frames_checked, 24);
    EXPECT_TRUE(report.crossing_frames.empty());
  }
  MorphReport none;
  check_frames(in.morph.manifold, 0.0, 1.0, in.VS, in.FS, in.VT, in.FT, none, {}, 0);
  EXPECT_EQ(none.crossing_frames_checked, 0);
}

namespace {

// An octahedron held over [0, 1], and beside it a small one that lasts only
// over [from, to]: two keyframes each, stitched (stitch.hpp) into one complex.
Complex octahedron_with_a_moment_of_company(double from, double to) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  Complex out;
  const Index k = V.rows();
  for (const auto& [offset, scale, t0, t1] : {std::tuple{0.0, 1.0, 0.0, 1.0}, std::tuple{5.0, 0.2, from, to}}) {
    StitchInput held;
    held.frames.resize(2 * k, 3);
    held.frames << (scale * V).array() + offset, (scale * V).array() + offset;
    held.faces = F;
    held.times.resize(2);
    held.times << t0, t1;
    const Complex part = stitch(held);
    const Index base = out.V.rows();
    out.V.conservativeResize(base + part.V.rows(), 4);
    out.V.bottomRows(part.V.rows()) = part.V;
    const Index first = out.S.rows();
    out.S.conservativeResize(first + part.S.rows(), 4);
    out.S.bottomRows(part.S.rows()) = part.S.array() + base;
  }
  return out;
}

}  // namespace

TEST(MorphValidity, CloserFramesFindWhatLastsLessThanTheSpreadFramesSpacing) {
  PointMatrix V;
  SimplexMatrix F;
  fixtures::octahedron(V, F);
  // The spread frames are 1/25 apart (0.48, 0.52 about the middle): an
  // island from 0.49 to 0.51 falls between them.
  const Complex manifold = octahedron_with_a_moment_of_company(0.49, 0.51);
  MorphReport spread;
  check_frames(manifold, 0.0, 1.0, V, F, V, F, spread);
  EXPECT_TRUE(spread.noise_frames.empty());
  EXPECT_EQ(spread.frames_checked, 24);
  MorphReport closer;
  check_frames(manifold, 0.0, 1.0, V, F, V, F, closer, {}, 24, {}, {0.485, 0.495, 0.5, 0.505, 0.515});
  // The three closer frames inside the island's moment, and the bisections
  // towards where it comes and goes: every noise frame inside it.
  ASSERT_GE(closer.noise_frames.size(), 3u);
  for (const double t : {0.495, 0.5, 0.505})
    EXPECT_NE(std::find(closer.noise_frames.begin(), closer.noise_frames.end(), t), closer.noise_frames.end()) << t;
  for (const double t : closer.noise_frames) EXPECT_TRUE(t >= 0.49 && t <= 0.51) << t;
  EXPECT_GT(closer.frames_checked, 24 + 5);
  EXPECT_EQ(closer.topology_changes, 2);
}
