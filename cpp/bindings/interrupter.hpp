// The core's Interrupter (animanifold/progress.hpp) from Python's callables,
// for every binding of a long call: `progress(step, fraction)` (False
// cancels) and `interrupted()` (True cancels), either may be None. Ctrl-C
// stops the call too, wherever it polls. The calls run with the GIL released
// (a morph may run in a worker thread, whose cancel button is the caller's
// interrupted()), so each callback takes the GIL.
#pragma once

#include "animanifold/progress.hpp"
#include "bindings.hpp"

#include <memory>
#include <string>

namespace animanifold::bindings {

// The Interrupter must be destroyed with the GIL held, in the binding's own
// scope: the callables are shared, not copied, so the core may copy the
// Interrupter with the GIL released.
inline Interrupter interrupter_from(const py::object& progress, const py::object& interrupted) {
  Interrupter out;
  if (!progress.is_none())
    out.progress = [callable = std::make_shared<py::object>(progress)](const std::string& step, double fraction) {
      py::gil_scoped_acquire acquire;
      return (*callable)(step, fraction).cast<bool>();
    };
  out.interrupted = [callable = std::make_shared<py::object>(interrupted)] {
    raise_pending_python_signals();
    if (callable->is_none()) return false;
    py::gil_scoped_acquire acquire;
    return (*callable)().cast<bool>();
  };
  return out;
}

// The docstring sentence every interruptible binding ends with.
inline constexpr const char* kInterrupterDoc =
    " `progress(step, fraction)` is called as each step starts and through long loops, with fractions growing "
    "in [0, 1]; `interrupted()` is polled with it; False from the one or True from the other raises Cancelled "
    "(so does Ctrl-C).";

}  // namespace animanifold::bindings
