#include "animanifold/progress.hpp"

#include "animanifold/errors.hpp"

#include <algorithm>

namespace animanifold {

void Interrupter::step(const std::string& name, double fraction) const {
  if (progress && !progress(name, std::clamp(fraction, 0.0, 1.0))) throw Cancelled();
  poll();
}

void Interrupter::poll() const {
  if (interrupted && interrupted()) throw Cancelled();
}

}  // namespace animanifold
