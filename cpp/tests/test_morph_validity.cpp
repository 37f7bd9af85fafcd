// check_frames (morph_validity.hpp) with work run beside the frames: the
// work runs once on any thread count, the frame checks report what they
// report without it, and what the work throws reaches the caller; crossings
// are checked on the spread frames asked for, and on the rest when asked
// once the work is done.
#include "animanifold/morph.hpp"
#include "animanifold/morph_validity.hpp"
#include "animanifold/threads.hpp"

#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <stdexcept>

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
