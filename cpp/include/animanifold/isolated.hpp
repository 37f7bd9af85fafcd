// Running a library call that can end the whole process in a child process.
//
// Debian builds TetGen 1.5 with its assert()s on: an assertion that fails
// inside tetrahedralize() calls abort(), and in Blender that would take the
// artist's session down with it (a morph of an unlucky input must fail the
// operator, never the program). run_isolated() forks, runs the work in the
// child and hands its result back through a pipe, so an abort, a
// segmentation fault or an exit() in the work only fails the call, and so
// does a child that runs past its time.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace animanifold {

// The work ended its process, or threw: what() says how (the signal, or the
// exception's own message).
struct IsolatedFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The child ran past `timeout_seconds` and was stopped: unlike the other
// failures, not a property of the work alone (a loaded machine, a child that
// hangs) — callers must not take it for the input's verdict.
struct IsolatedTimeout : IsolatedFailure {
  using IsolatedFailure::IsolatedFailure;
};

// Inputs:
//   work             the call to isolate; returns bytes
//   timeout_seconds  > 0: the child's time limit
//   while_waiting    optional poll, about every kWaitTick seconds
// Outputs:
//   the bytes `work` returned
// Throws: IsolatedFailure (see below); whatever while_waiting throws
//
// Runs `work` in a forked child process and returns the bytes it returned.
// Throws IsolatedFailure when the child ends any other way: killed by a
// signal (an assertion's SIGABRT, a SIGSEGV), exiting on its own, or by an
// exception thrown in `work` (its message is carried over). The child shares
// nothing with the caller afterwards: what `work` changes in memory is lost,
// only the bytes come back. The child's own parallel loops run on one
// thread (the parent's OpenMP threads are not copied into it). Where fork() fails, and in a ThreadSanitizer
// build (whose forked children can deadlock), `work` runs in this process.
// `timeout_seconds` > 0: a child that has not finished by then is killed and
// IsolatedTimeout (an IsolatedFailure) says so (TetGen 1.5 can loop for ever recovering the facets
// of a fan of cocircular points; a morph must fail, not hang Blender).
// `while_waiting`, when given, is called about every kWaitTick seconds while
// the child runs; what it throws (a Ctrl-C the caller noticed, a cancel) stops
// the child and is rethrown: long work stays interruptible.
std::vector<char> run_isolated(const std::function<std::vector<char>()>& work, double timeout_seconds = 0,
                               const std::function<void()>& while_waiting = {});

// How often run_isolated calls `while_waiting`, in seconds.
constexpr double kWaitTick = 0.1;

}  // namespace animanifold
