// How a long core call tells its caller how far it is, and learns that it
// should stop: the one interrupter of morph, voronoi_skeleton, the Deformer
// (factorisation, deform, restore), subdivide_manifold, subdivide_frame,
// subdivide_polyline and stitch (in the spirit of OpenVDB's
// util::NullInterrupter: a step name, a fraction, a was-interrupted check).
//
// A call reports each of its named steps as it starts, and the chunks of its
// long loops, through step(); the fractions it passes only grow, from 0 to 1.
// An empty Interrupter (the default argument everywhere) costs nothing.
// Python passes its callables through cpp/bindings/interrupter.hpp, which
// also stops the call on Ctrl-C.
#pragma once

#include <functional>
#include <string>

namespace animanifold {

struct Interrupter {
  // Called with (step, fraction of the call done, in [0, 1]); returning false
  // cancels the call.
  std::function<bool(const std::string& step, double fraction)> progress;
  // Polled with every step() (and, in a morph, about every 0.1 s while a
  // mesher runs in its child process); returning true cancels the call.
  std::function<bool()> interrupted;

  // Inputs:
  //   name      the step the call is in ("factorising", "bisectors")
  //   fraction  how much of the call is done; clamped to [0, 1]
  // Throws:
  //   Cancelled  when progress() returns false or interrupted() returns true
  void step(const std::string& name, double fraction) const;
  // Outputs: nothing: returns when the call may go on (progress is not called)
  // Throws:
  //   Cancelled  when interrupted() returns true
  void poll() const;
};

// Inputs:
//   from, to     the span of the call's [0, 1] the loop takes
//   done, total  items of the loop finished, and all of them
// Outputs: from + (to - from) * done / total, the fraction to pass to step() inside
//   a long loop; `to` when total <= 0
// Throws: nothing
inline double loop_fraction(double from, double to, long long done, long long total) {
  return total <= 0 ? to : from + (to - from) * static_cast<double>(done) / static_cast<double>(total);
}

}  // namespace animanifold
