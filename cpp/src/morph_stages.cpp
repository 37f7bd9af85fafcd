#include "morph_stages.hpp"

#include "animanifold/isolated.hpp"

#include <thread>

namespace animanifold {

StageClock::StageClock(const MorphOptions& options) : options_(options) {}

void StageClock::finish() {
  if (running_.empty()) return;
  const auto now = std::chrono::steady_clock::now();
  seconds.emplace_back(running_, std::chrono::duration<double>(now - started_).count());
  running_.clear();
}

void StageClock::begin(const std::string& name, double fraction) {
  finish();
  running_ = name;
  started_ = std::chrono::steady_clock::now();
  advance(fraction);
  if (!options_.hold_stage.empty() && options_.hold_stage == name && options_.hold_seconds > 0) {
    const double hold = options_.hold_seconds;
    run_isolated(
        [hold] {
          std::this_thread::sleep_for(std::chrono::duration<double>(hold));
          return std::vector<char>{};
        },
        0, while_waiting());
  }
}

void StageClock::advance(double fraction) {
  if (options_.progress && !options_.progress(running_, fraction)) throw Cancelled();
}

std::function<void()> StageClock::while_waiting() const {
  if (!options_.interrupted) return {};
  const MorphOptions* options = &options_;
  return [options] {
    if (options->interrupted()) throw Cancelled();
  };
}

}  // namespace animanifold
