// The stage clock every morph method runs its stages under: timing, progress,
// cancellation, and a hold for tests (morph.hpp's MorphOptions).
//
// begin(name, fraction) ends the running stage (its seconds go to
// `seconds`), tells the caller's progress() that `name` starts at `fraction`
// of the morph (returning false cancels: Cancelled is thrown), and, where
// MorphOptions::hold_stage names it, first runs a stand-in child process that
// sleeps MorphOptions::hold_seconds under the same polling as TetGen's
// (run_isolated): tests of Esc and Ctrl-C then do not depend on a library
// being slow on some input. while_waiting() is what a child process's wait
// polls: the caller's interrupted() (a cancel button, Ctrl-C).
#pragma once

#include "animanifold/morph.hpp"

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace animanifold {

// Where MorphOptions::hold_stage is `stage`: a stand-in child process sleeps
// MorphOptions::hold_seconds under run_isolated's polling of interrupted().
// The seed's methods hold here before their mesher runs ("conforming").
void hold_for_tests(const MorphOptions& options, const std::string& stage);

// The poll a child process's wait runs: the caller's interrupted(), which
// throws Cancelled when it says so. Empty when there is no interrupted().
std::function<void()> interrupt_poll(const MorphOptions& options);

class StageClock {
 public:
  explicit StageClock(const MorphOptions& options);
  void begin(const std::string& name, double fraction);
  // Ends the running stage.
  void finish();
  // Polls the caller's interrupted(); throws Cancelled when it says so.
  std::function<void()> while_waiting() const;
  // Tells progress() how far the running stage is (fraction of the morph);
  // false from it cancels.
  void advance(double fraction);

  std::vector<std::pair<std::string, double>> seconds;

 private:
  const MorphOptions& options_;
  std::string running_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace animanifold
