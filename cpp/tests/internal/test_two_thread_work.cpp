// lead_and_beside() (two_thread_work.hpp): every task runs once, never
// before the task it needs has finished nor before the lead; a failure
// skips the tasks not yet started and reaches the caller; one thread runs
// the same work in turn.
#include "two_thread_work.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace animanifold {
namespace {

// What happened, in order: "lead", "beside", or a task's index.
class Journal {
 public:
  void write(int event) {
    const std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back(event);
  }
  std::vector<int> events() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return events_;
  }

 private:
  std::mutex mutex_;
  std::vector<int> events_;
};

constexpr int kLead = -1, kBeside = -2;
constexpr int kFinished = 100;  // task t writes t when it starts, kFinished + t when it ends

// A chain and a fan of tasks, some slow, so that the two threads interleave.
std::vector<AfterTask> tasks(Journal& journal, const std::vector<int>& needs) {
  std::vector<AfterTask> out;
  for (size_t t = 0; t < needs.size(); ++t) {
    const int task = static_cast<int>(t);
    out.push_back({[&journal, task] {
                     journal.write(task);
                     std::this_thread::sleep_for(std::chrono::milliseconds(task % 3 == 0 ? 20 : 2));
                     journal.write(kFinished + task);
                   },
                   needs[t]});
  }
  return out;
}

size_t position(const std::vector<int>& events, int event) {
  for (size_t i = 0; i < events.size(); ++i)
    if (events[i] == event) return i;
  return events.size();
}

void expect_every_task_once_after_what_it_needs(int threads) {
  const int before = set_thread_count(threads);
  Journal journal;
  const std::vector<int> needs = {-1, 0, 1, -1, 3, 0, 5, 2, -1};
  lead_and_beside(
      [&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        journal.write(kLead);
      },
      [&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        journal.write(kBeside);
      },
      tasks(journal, needs));
  set_thread_count(before);
  const std::vector<int> events = journal.events();
  ASSERT_EQ(events.size(), 2 + 2 * needs.size());
  for (int task = 0; task < static_cast<int>(needs.size()); ++task) {
    const size_t start = position(events, task), end = position(events, kFinished + task);
    ASSERT_LT(start, end) << "task " << task << " started once and finished";
    EXPECT_GT(start, position(events, kLead)) << "task " << task << " started before the lead finished";
    if (needs[task] >= 0)
      EXPECT_GT(start, position(events, kFinished + needs[task]))
          << "task " << task << " started before task " << needs[task] << " finished";
  }
}

TEST(LeadAndBeside, RunsEveryTaskOnceAfterTheLeadAndAfterTheTaskItNeedsOnTwoThreads) {
  expect_every_task_once_after_what_it_needs(2);
}

TEST(LeadAndBeside, RunsTheSameWorkInTurnOnOneThread) { expect_every_task_once_after_what_it_needs(1); }

TEST(LeadAndBeside, AFailingTaskSkipsTheTasksNotStartedAndReachesTheCaller) {
  const int before = set_thread_count(2);
  Journal journal;
  std::vector<AfterTask> after = tasks(journal, {-1, 0, 1, 2});
  after[1].run = [] { throw std::runtime_error("task 1 failed"); };
  EXPECT_THROW(lead_and_beside([] {}, [] {}, after), std::runtime_error);
  set_thread_count(before);
  const std::vector<int> events = journal.events();
  // Tasks 2 and 3 need task 1 (through 2): neither started.
  EXPECT_EQ(position(events, 2), events.size());
  EXPECT_EQ(position(events, 3), events.size());
}

TEST(LeadAndBeside, AFailingLeadRunsNoTaskAndReachesTheCallerAfterTheBesideWork) {
  const int before = set_thread_count(2);
  Journal journal;
  EXPECT_THROW(lead_and_beside([] { throw std::runtime_error("lead failed"); }, [&] { journal.write(kBeside); },
                               tasks(journal, {-1, -1})),
               std::runtime_error);
  set_thread_count(before);
  EXPECT_EQ(journal.events(), std::vector<int>{kBeside});
}

TEST(LeadAndBeside, RefusesATaskThatNeedsOneAfterIt) {
  Journal journal;
  EXPECT_THROW(lead_and_beside([] {}, [] {}, tasks(journal, {1, -1})), InputError);
}

}  // namespace
}  // namespace animanifold
