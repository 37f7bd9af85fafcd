// The exception hierarchy of the core: every exception a core call throws on
// purpose is one of the types below. Every message names what was wrong and
// where (which keyframe, vertex, face or simplex).
//
// Python (cpp/bindings/bind_errors.cpp) sees each as a subclass of
// animanifold.Error and of the builtin it has always mapped to:
//   InputError   -> _core.InputError(Error, ValueError)
//   IOError      -> _core.FileError(Error, OSError)
//   BooleanError -> _core.BooleanError(Error, RuntimeError)
//   MeshingError -> _core.MeshingError(Error, RuntimeError)
//   TimeLimitError -> _core.TimeLimitError(MeshingError)
//   Cancelled    -> _core.Cancelled(Error)
//   MemoryLimitError -> _core.MemoryLimitError(Error, MemoryError)
#pragma once

#include <exception>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace animanifold {

// The caller's data is invalid (bad shape, NaN, index out of range, ...).
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Faces that do not form an oriented 2-manifold surface where a call needs
// one (two parts pinched at a vertex, an edge of three faces, a flipped
// face): an InputError that callers with another way (winding numbers) can
// tell from the rest.
struct NotManifoldError : InputError {
  using InputError::InputError;
};

// A file could not be read or written, or its contents are damaged.
struct IOError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// CGAL refused an operand of a Boolean operation, or the result would not be
// a manifold (hole_space.hpp).
struct BooleanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A library we call to mesh, triangulate or factor (TetGen, Qhull, CGAL,
// CHOLMOD) failed, or its result breaks what we rely on (a fill that does not
// conform to its constraints). The message says what we were doing and on
// which input, with the library's own text at the end.
struct MeshingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A library call ran past the time limit kept as a safety net against a
// library that loops (TetGen on some inputs): it was stopped. Never a reason
// to try again another way (another perturbation): whether the limit is hit
// depends on the machine's speed and load, and a result must not. A
// MeshingError, so that its handlers see it; retries let it pass.
struct TimeLimitError : MeshingError {
  using MeshingError::MeshingError;
};

// The caller's progress or interrupt callback asked a long call to stop.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

// A call's estimated memory exceeds the limit (memory_limit.hpp); nothing was allocated.
// The message names the call, the estimate and the limit. A std::bad_alloc, so that
// translating_library_failures (below) and every handler of running out of memory pass it on.
class MemoryLimitError : public std::bad_alloc {
 public:
  explicit MemoryLimitError(std::string message) : message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

// Inputs:
//   Error  the exception type to throw (constructible from a string)
//   parts  streamable parts of the message: fail<InputError>("keyframe ", i, " ...")
// Outputs: none: it never returns
// Throws: Error with the parts streamed one after the other as its message
template <class Error, class... Parts>
[[noreturn]] void fail(Parts&&... parts) {
  std::ostringstream message;
  (message << ... << std::forward<Parts>(parts));
  throw Error(message.str());
}

// Inputs:
//   e  what a library threw
// Outputs: the library's own explanation of the failure: e.what() (the default
//   `reason` of translating_library_failures)
// Throws: nothing (beyond std::bad_alloc)
inline std::string library_reason(const std::exception& e) { return e.what(); }

// Runs `work` (a call into `library`) and turns what the library throws into
// an `Error` (MeshingError unless the caller names another):
// "<library> failed while <doing>: <reason(e)>", so that callers see one type
// in our words with the library's reason kept. Our own errors and running out
// of memory pass through unchanged.
//
// Inputs:
//   library  the library's name as messages show it ("CGAL", "TetGen")
//   doing    what we were doing, with its size ("triangulating 12 points in R^4")
//   work     the call into the library; its result is returned
//   reason   extracts the library's explanation from its exception
// Throws:
//   Error    when `work` throws anything but our errors or std::bad_alloc
template <class Error = MeshingError, class Work, class Reason = std::string (*)(const std::exception&)>
auto translating_library_failures(const char* library, const std::string& doing, Work&& work,
                                  Reason reason = &library_reason) -> decltype(work()) {
  try {
    return work();
  } catch (const InputError&) {
    throw;
  } catch (const IOError&) {
    throw;
  } catch (const BooleanError&) {
    throw;
  } catch (const MeshingError&) {
    throw;
  } catch (const Cancelled&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    fail<Error>(library, " failed while ", doing, ": ", reason(e));
  }
}

}  // namespace animanifold
