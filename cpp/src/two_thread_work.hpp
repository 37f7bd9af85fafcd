// Work for two threads, as the field method splits it (morph_field.cpp):
// the two ends' sides side by side, and a long call beside a lead and the
// tasks that follow it. Both run in turn when the thread setting allows
// one thread only: the same work, so the same bits.
#pragma once

#include "animanifold/errors.hpp"
#include "animanifold/threads.hpp"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

namespace animanifold {

// Runs work(0) and work(1) (the source's side and the target's), each on a
// thread of its own when the thread setting allows two: the sides share
// nothing they write, and each side's work is the same serial work either
// way (OpenMP inside it runs on its one thread), so the bits are too.
template <class Work>
void on_both_sides(Work&& work) {
  std::exception_ptr failure[2];
#pragma omp parallel for schedule(static, 1) num_threads(std::min(2, thread_count()))
  for (int side = 0; side < 2; ++side) {
    try {
      work(side);
    } catch (...) {
      failure[side] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : failure)
    if (e) std::rethrow_exception(e);
}

// A task lead_and_beside() runs after lead(), and the earlier task of the
// list (its index) that must have finished before it starts, if any.
struct AfterTask {
  std::function<void()> run;
  int needs = -1;
};

// Runs lead() on one thread and beside() on the other, then the `after`
// tasks (which need lead()'s results; each writes its own), each on
// whichever thread is free first: the first task in the list whose
// prerequisite is done, when the thread setting allows two (else lead, the
// tasks, then beside: the same work, so the same bits). A thread with no
// task ready waits for the other's; a task needs one before it in the list,
// so the first task not started is always ready when neither runs one. A
// failure of lead() or of a task skips the tasks not yet started; the first
// failure is thrown once both threads are done.
template <class Lead, class Beside>
void lead_and_beside(Lead&& lead, Beside&& beside, const std::vector<AfterTask>& after) {
  for (size_t task = 0; task < after.size(); ++task)
    if (after[task].needs >= static_cast<int>(task)) fail<InputError>("an after-task may only need an earlier one");
  enum class State : char { Waiting, Running, Done };
  std::mutex mutex;
  std::condition_variable changed;
  bool lead_finished = false, failed = false;
  std::vector<State> state(after.size(), State::Waiting);
  auto settle = [&](auto&& change) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      change();
    }
    changed.notify_all();
  };
  // The first task ready, or after.size() when none is; `pending`: whether
  // some task has not started.
  auto first_ready = [&](bool& pending) {
    pending = false;
    for (size_t task = 0; task < after.size(); ++task) {
      if (state[task] != State::Waiting) continue;
      pending = true;
      const int needs = after[task].needs;
      if (needs < 0 || state[static_cast<size_t>(needs)] == State::Done) return task;
    }
    return after.size();
  };
  auto run_after = [&] {
    for (;;) {
      size_t task = after.size();
      {
        std::unique_lock<std::mutex> lock(mutex);
        bool pending = true;
        changed.wait(lock, [&] { return failed || (task = first_ready(pending)) < after.size() || !pending; });
        if (failed || !pending) return;
        state[task] = State::Running;
      }
      try {
        after[task].run();
      } catch (...) {
        settle([&] { failed = true; });
        throw;
      }
      settle([&] { state[task] = State::Done; });
    }
  };
  on_both_sides([&](int side) {
    if (side == 0) {
      try {
        lead();
      } catch (...) {
        settle([&] { lead_finished = failed = true; });
        throw;
      }
      settle([&] { lead_finished = true; });
      run_after();
      return;
    }
    beside();
    {
      std::unique_lock<std::mutex> lock(mutex);
      changed.wait(lock, [&] { return lead_finished; });
    }
    run_after();
  });
}

}  // namespace animanifold
