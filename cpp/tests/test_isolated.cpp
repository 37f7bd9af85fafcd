// run_isolated (isolated.hpp): the work's bytes come back; an abort, a crash,
// an exit or an exception in it fail the call and leave this process running.
#include "animanifold/isolated.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
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
    run_isolated([]() -> std::vector<char> { std::abort(); });
    FAIL() << "no failure reported";
  } catch (const IsolatedFailure& e) {
    EXPECT_NE(std::string(e.what()).find("SIGABRT"), std::string::npos) << e.what();
  }
  // and this process goes on: a second call works
  EXPECT_EQ(run_isolated([] { return std::vector<char>{'o', 'k'}; }).size(), 2u);
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

TEST(Isolated, WorkPastItsTimeIsStoppedAndReported) {
  const auto start = std::chrono::steady_clock::now();
  try {
    run_isolated([]() -> std::vector<char> { for (volatile bool on = true; on;) {} return {}; }, 0.5);
    FAIL() << "no failure reported";
  } catch (const IsolatedFailure& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish within"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  // work that finishes in time, with a big result, comes back whole
  const std::vector<char> big(300000, 'y');
  EXPECT_EQ(run_isolated([&] { return big; }, 30.0), big);
}

TEST(Isolated, WhatTheWorkChangesStaysInTheChild) {
  int counter = 0;
  run_isolated([&] {
    ++counter;
    return std::vector<char>{};
  });
  EXPECT_EQ(counter, 0);
}

}  // namespace
}  // namespace animanifold
