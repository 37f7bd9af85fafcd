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
  hold_for_tests(options_, name);
}

void StageClock::advance(double fraction) {
  if (options_.interrupter.progress && !options_.interrupter.progress(running_, fraction)) throw Cancelled();
}

std::function<void()> StageClock::while_waiting() const { return interrupt_poll(options_); }

std::function<void()> interrupt_poll(const MorphOptions& options) {
  if (!options.interrupter.interrupted) return {};
  return [&interrupter = options.interrupter] { interrupter.poll(); };
}

void hold_for_tests(const MorphOptions& options, const std::string& stage) {
  if (options.hold_stage.empty() || options.hold_stage != stage || !(options.hold_seconds > 0)) return;
  const double hold = options.hold_seconds;
  run_isolated(
      [hold] {
        std::this_thread::sleep_for(std::chrono::duration<double>(hold));
        return std::vector<char>{};
      },
      0, interrupt_poll(options));
}

}  // namespace animanifold
