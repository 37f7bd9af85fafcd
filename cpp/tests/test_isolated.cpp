// run_isolated (isolated.hpp): the work's bytes come back; an abort, a crash,
// an exit or an exception in it fail the call and leave this process running.
#include "animanifold/isolated.hpp"
#include "animanifold/threads.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace animanifold {
namespace {

TEST(Isolated, ReturnsTheBytesOfTheWork) {
  const std::vector<char> big(300000, 'x');  // more than a pipe holds at once
  EXPECT_EQ(run_isolated([] { return std::vector<char>{'a', 'b', 'c'}; }), (std::vector<char>{'a', 'b', 'c'}));
  EXPECT_EQ(run_isolated([&] { return big; }), big);
  EXPECT_TRUE(run_isolated([] { return std::vector<char>{}; }).empty());
}

TEST(Isolated, AnAbortFailsTheCallNotTheProcess) {
  try {
    run_isolated([]() -> std::vector<char> { std::abort(); }, 30.0);
    FAIL() << "no failure reported";
  } catch (const IsolatedTimeout& e) {
    FAIL() << "an abort taken for a time limit: " << e.what();
  } catch (const IsolatedFailure& e) {
    EXPECT_NE(std::string(e.what()).find("SIGABRT"), std::string::npos) << e.what();
  }
  // and this process goes on: a second call works
  EXPECT_EQ(run_isolated([] { return std::vector<char>{'o', 'k'}; }).size(), 2u);
}

// A handler of the parent's (Blender's crash log, a fuzzer's report) does not run in the
// child: its crash ends it by the signal, as if no handler were installed.
TEST(Isolated, TheParentsCrashHandlersDoNotRunInTheChild) {
  const auto exit_42 = [](int) { std::_Exit(42); };
  for (int signal : {SIGABRT, SIGSEGV}) {
    const auto previous = std::signal(signal, +exit_42);
    try {
      run_isolated([signal]() -> std::vector<char> {
        std::raise(signal);
        return {};
      });
      ADD_FAILURE() << "no failure reported";
    } catch (const IsolatedFailure& e) {
      EXPECT_NE(std::string(e.what()).find(signal == SIGABRT ? "SIGABRT" : "SIGSEGV"), std::string::npos) << e.what();
    }
    std::signal(signal, previous);
  }
}

// A library's chatter in the child (TetGen prints what it found) stays out of the console;
// the parent's own output is untouched.
TEST(Isolated, WhatTheChildPrintsDoesNotReachStandardOutput) {
  testing::internal::CaptureStdout();
  std::printf("parent before; ");
  const auto bytes = run_isolated([] {
    std::printf("chatter from the library\n");
    std::fflush(stdout);
    return std::vector<char>{'o', 'k'};
  });
  std::printf("parent after");
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "parent before; parent after");
  EXPECT_EQ(bytes.size(), 2u);
}

TEST(Isolated, ACrashAndAnExitAreReported) {
  EXPECT_THROW(run_isolated([]() -> std::vector<char> {
                 volatile int* nowhere = nullptr;
                 *nowhere = 1;
                 return {};
               }),
               IsolatedFailure);
  try {
    run_isolated([]() -> std::vector<char> { std::_Exit(7); });
    FAIL() << "no failure reported";
  } catch (const IsolatedFailure& e) {
    EXPECT_NE(std::string(e.what()).find("status 7"), std::string::npos) << e.what();
  }
}

TEST(Isolated, AnExceptionsMessageIsCarriedOver) {
  try {
    run_isolated([]() -> std::vector<char> { throw std::runtime_error("the constraints intersect each other"); });
    FAIL() << "no failure reported";
  } catch (const IsolatedFailure& e) {
    EXPECT_STREQ(e.what(), "the constraints intersect each other");
  }
}

// A time limit hit is told apart from the work's own failures (IsolatedTimeout):
// it depends on the machine, and callers must not take it for the input's verdict.
TEST(Isolated, WorkPastItsTimeIsStoppedAndReported) {
  const auto start = std::chrono::steady_clock::now();
  try {
    run_isolated([]() -> std::vector<char> { for (volatile bool on = true; on;) {} return {}; }, 0.5);
    FAIL() << "no failure reported";
  } catch (const IsolatedTimeout& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish within"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  // work that finishes in time, with a big result, comes back whole
  const std::vector<char> big(300000, 'y');
  EXPECT_EQ(run_isolated([&] { return big; }, 30.0), big);
}

// What the caller's wait throws (a cancel, Ctrl-C) stops the child at once
// and comes out of the call; work that finishes is waited on in ticks and
// comes back whole.
TEST(Isolated, WhatTheWaitThrowsStopsTheChildAndComesOut) {
  struct Interrupt {};
  // A fresh name in the temporary folder ($TMPDIR or /tmp); the child writes
  // the file if it lives past one second.
  std::string name = (std::filesystem::temp_directory_path() / "animanifold_isolated_XXXXXX").string();
  const int fd = ::mkstemp(name.data());
  ASSERT_GE(fd, 0) << name;
  ::close(fd);
  ::unlink(name.c_str());
  const std::string path = name;
  int ticks = 0;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(run_isolated(
                   [&]() -> std::vector<char> {
                     std::this_thread::sleep_for(std::chrono::seconds(1));
                     std::FILE* f = std::fopen(path.c_str(), "w");
                     if (f) std::fclose(f);
                     std::this_thread::sleep_for(std::chrono::seconds(30));
                     return {};
                   },
                   0, [&] {
                     if (++ticks == 3) throw Interrupt{};
                   }),
               Interrupt);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(ticks, 3);
  EXPECT_LT(waited, 0.9);  // three ticks of 0.1 s, not the work's 31 s
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_NE(::access(path.c_str(), F_OK), 0) << "the child was still running after the call";
  ::unlink(path.c_str());

  ticks = 0;
  const std::vector<char> result = run_isolated(
      [] {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        return std::vector<char>{'o', 'k'};
      },
      30.0, [&] { ++ticks; });
  EXPECT_EQ(result, (std::vector<char>{'o', 'k'}));
  EXPECT_GE(ticks, 3);
}

TEST(Isolated, WhatTheWorkChangesStaysInTheChild) {
  int counter = 0;
  run_isolated([&] {
    ++counter;
    return std::vector<char>{};
  });
  EXPECT_EQ(counter, 0);
}

TEST(Isolated, TheChildsParallelLoopsRunAfterTheParentsTeamsHaveRun) {
  // libgomp's threads of the parent are not in the child: a team of two there
  // would wait for them for ever, so the child runs its loops on one thread.
  const int before = thread_count();
  set_thread_count(2);
  ASSERT_EQ(parallel_team_size(), 2);
  const std::vector<char> child = run_isolated([] { return std::vector<char>{static_cast<char>(parallel_team_size())}; },
                                               30.0);
  EXPECT_EQ(thread_count(), 2) << "the child's setting leaked into the parent";
  set_thread_count(before);
  ASSERT_EQ(child.size(), 1u);
  EXPECT_EQ(child[0], 1);
}

}  // namespace
}  // namespace animanifold
