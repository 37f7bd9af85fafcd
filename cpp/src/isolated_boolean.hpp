// One Boolean operation of the hole spaces run in a child process (isolated.hpp), under a
// time limit and the caller's interrupter.
//
// CGAL's corefinement can loop for ever on some inputs (with its assertions on it never
// leaves append_patches_to_triangle_mesh on inputs a release build finishes at once). In
// Blender that would hang the artist's session with no way out, so every Boolean runs in a
// child: Esc, Ctrl-C and the interrupter stop it while it runs, and a child past its time
// limit is killed and reported as such (TimeLimitError), never as a verdict on the operands. Our own errors raised in the child (InputError,
// BooleanError) come back as themselves, with their messages.
#pragma once

#include "animanifold/hole_space.hpp"
#include "animanifold/progress.hpp"

#include <functional>
#include <string>

namespace animanifold::holes {

// What a Boolean operation made: the solid, and whether it differs from the first operand
// (boolean_3d/boolean_2d return false when the boundaries do not meet).
struct BooleanOutcome {
  Solid solid;
  bool changed = true;
};

// Inputs:
//   faces  the operands' faces together
// Outputs: the seconds a Boolean of that size may run: far beyond what a finishing one takes
//   (under a second for every model of the shared data), so only a loop reaches it
// Throws: nothing
double boolean_time_limit(Index faces);

// Inputs:
//   doing               what the operation is, for messages ("subtracting a solid from the frame")
//   work                the operation; runs in the child
//   time_limit_seconds  > 0: the child is killed after that long
//   interrupter         polled before the child starts and about every 0.1 s while it runs
// Outputs: what `work` returned
// Throws: InputError or BooleanError that `work` threw, with its message; TimeLimitError naming
//   `doing` when the child runs past its time limit (it is killed); BooleanError naming `doing`
//   when it runs out of memory or ends any other way (a signal); Cancelled when the interrupter
//   says so (the child is killed)
BooleanOutcome isolated_boolean(const std::string& doing, const std::function<BooleanOutcome()>& work,
                                double time_limit_seconds, const Interrupter& interrupter);

}  // namespace animanifold::holes
