// Internal to slicing: timing a slice's stages into a SliceStages, when one is asked for.
#pragma once

#include "animanifold/slice.hpp"

#include <chrono>

namespace animanifold {

// Adds the time since the last lap (or construction, or restart) to a field
// of `stages`; does nothing without one.
class StageClock {
 public:
  explicit StageClock(SliceStages* stages) : stages_(stages) { restart(); }
  void restart() {
    if (stages_) last_ = std::chrono::steady_clock::now();
  }
  void lap(double SliceStages::*field) {
    if (!stages_) return;
    const auto now = std::chrono::steady_clock::now();
    stages_->*field += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  SliceStages* stages_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace animanifold
