// The exception hierarchy of the core. Every message names what was wrong and
// where (which keyframe, vertex, face or simplex); the binding maps
// InputError to Python's ValueError and the rest to RuntimeError.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace animanifold {

// The caller's data is invalid (bad shape, NaN, index out of range, ...).
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A file could not be read or written, or its contents are damaged.
struct IOError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Builds a message from streamable parts: fail<InputError>("keyframe ", i, " ...").
template <class Error, class... Parts>
[[noreturn]] void fail(Parts&&... parts) {
  std::ostringstream message;
  (message << ... << std::forward<Parts>(parts));
  throw Error(message.str());
}

}  // namespace animanifold
