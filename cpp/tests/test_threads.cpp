// The core's thread count (threads.hpp): what is set is what is read and what
// a core loop gets, 0 is every core, anything else is refused and changes
// nothing, and a loop started from another thread gets the same count.
// That results do not depend on the count is tests/test_thread_count.py's.
#include "animanifold/threads.hpp"

#include "animanifold/errors.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <climits>
#include <string>
#include <thread>

using namespace animanifold;

namespace {

// Each test leaves the count as it found it: the other tests of the binary
// run on whatever count the process has.
class Threads : public ::testing::Test {
 protected:
  void SetUp() override { before_ = thread_count(); }
  void TearDown() override { set_thread_count(before_); }

 private:
  int before_ = 0;
};

std::string input_error_of(int count) {
  return fixtures::input_error_message([&] { set_thread_count(count); });
}

}  // namespace

TEST_F(Threads, TheCountSetIsTheCountReadAndTheTeamOfACoreLoop) {
  for (int count : {1, 2, 3}) {
    SCOPED_TRACE(count);
    EXPECT_EQ(set_thread_count(count), count);
    EXPECT_EQ(thread_count(), count);
    EXPECT_EQ(parallel_team_size(), count);
  }
}

TEST_F(Threads, ZeroMeansEveryCore) {
  const int every = set_thread_count(0);
  EXPECT_EQ(every, omp_get_num_procs());
  EXPECT_GE(every, 1);
  EXPECT_EQ(thread_count(), every);
  EXPECT_EQ(parallel_team_size(), every);
}

TEST_F(Threads, ANegativeOrTooLargeCountIsRefusedNamingItAndChangesNothing) {
  set_thread_count(2);
  EXPECT_EQ(input_error_of(-1), "thread count must be >= 1, or 0 for every core; got -1");
  EXPECT_EQ(input_error_of(INT_MIN), "thread count must be >= 1, or 0 for every core; got " + std::to_string(INT_MIN));
  EXPECT_EQ(input_error_of(kMaxThreads + 1),
            "thread count " + std::to_string(kMaxThreads + 1) + " is more than " + std::to_string(kMaxThreads));
  EXPECT_EQ(input_error_of(INT_MAX), "thread count " + std::to_string(INT_MAX) + " is more than " +
                                         std::to_string(kMaxThreads));
  EXPECT_EQ(thread_count(), 2);
  EXPECT_EQ(parallel_team_size(), 2);
}

TEST_F(Threads, ALoopStartedFromAnotherThreadGetsTheCountSetInThisOne) {
  set_thread_count(3);
  int team = 0, count = 0;
  std::thread other([&] {
    count = thread_count();
    team = parallel_team_size();
  });
  other.join();
  EXPECT_EQ(count, 3);
  EXPECT_EQ(team, 3);
}

TEST_F(Threads, ApplyingTheCountSetsTheCallingThreadsOpenMPSetting) {
  set_thread_count(3);
  int before = 0, after = 0;
  std::thread other([&] {
    omp_set_num_threads(1);  // what a thread may hold from elsewhere
    before = omp_get_max_threads();
    apply_thread_count();
    after = omp_get_max_threads();
  });
  other.join();
  EXPECT_EQ(before, 1);
  EXPECT_EQ(after, 3);
}

TEST_F(Threads, OpenBLASFollowsTheCount) {
  if (blas_thread_count() == 0) GTEST_SKIP() << "the process's BLAS is not OpenBLAS";
  for (int count : {1, 2}) {
    set_thread_count(count);
    EXPECT_EQ(blas_thread_count(), count);
  }
}
