// CGAL's failures in our words: every call into CGAL that can throw runs
// under translating_cgal_failures, so a caller (and Python) sees one of our
// errors naming what we were doing, with CGAL's explanation kept.
#pragma once

#include "animanifold/errors.hpp"

#include <CGAL/exceptions.h>

#include <exception>
#include <string>

namespace animanifold {

// CGAL's explanation of why it failed: its own exceptions carry the failed
// condition and a message on several lines; other exceptions thrown from
// inside CGAL (e.g. Constrained_triangulation_2's "Unauthorized
// intersections of constraints", raised by the corefinement's face
// triangulation) only a what().
inline std::string cgal_reason(const std::exception& e) {
  if (const auto* failure = dynamic_cast<const CGAL::Failure_exception*>(&e))
    return !failure->message().empty() ? failure->message() : failure->expression();
  return e.what();
}

// Runs `work` (a call into CGAL) and turns what CGAL throws into an `Error`
// (MeshingError unless named): "CGAL failed while <doing>: <CGAL's reason>".
//
// Inputs:
//   doing  what we were doing, with its size ("building the distance tree of 12 triangles")
//   work   the call into CGAL; its result is returned
// Throws:
//   Error  when CGAL throws; our own errors and std::bad_alloc pass through
template <class Error = MeshingError, class Work>
auto translating_cgal_failures(const std::string& doing, Work&& work) -> decltype(work()) {
  return translating_library_failures<Error>("CGAL", doing, std::forward<Work>(work), &cgal_reason);
}

}  // namespace animanifold
