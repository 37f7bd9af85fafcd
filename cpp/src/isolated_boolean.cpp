// isolated_boolean (isolated_boolean.hpp): the child's answer as bytes, a tag first.
#include "isolated_boolean.hpp"

#include "animanifold/errors.hpp"
#include "animanifold/isolated.hpp"

#include <cstdint>
#include <cstring>
#include <new>
#include <vector>

namespace animanifold::holes {

namespace {

// The first byte of the child's answer: a solid follows, or an error's message.
enum Tag : char { kSolid = 'S', kInputError = 'I', kBooleanError = 'B', kOutOfMemory = 'M' };

void put(std::vector<char>& bytes, const void* data, std::size_t size) {
  const std::size_t at = bytes.size();
  bytes.resize(at + size);
  if (size > 0) std::memcpy(bytes.data() + at, data, size);
}

template <class Matrix>
void put_matrix(std::vector<char>& bytes, const Matrix& m) {
  const std::int64_t shape[2] = {m.rows(), m.cols()};
  put(bytes, shape, sizeof shape);
  put(bytes, m.data(), sizeof(typename Matrix::Scalar) * static_cast<std::size_t>(m.size()));
}

std::vector<char> packed(const BooleanOutcome& outcome) {
  std::vector<char> bytes{kSolid, static_cast<char>(outcome.changed)};
  put_matrix(bytes, outcome.solid.vertices);
  put_matrix(bytes, outcome.solid.faces);
  return bytes;
}

std::vector<char> packed_error(Tag tag, const char* message) {
  std::vector<char> bytes{tag};
  put(bytes, message, std::strlen(message));
  return bytes;
}

// Reads what packed() wrote; the bytes come from our own child, so their shapes are trusted
// only as far as the byte count confirms them.
struct Reader {
  const std::vector<char>& bytes;
  std::size_t at = 2;

  template <class Matrix>
  Matrix matrix(const std::string& doing) {
    std::int64_t shape[2];
    take(shape, sizeof shape, doing);
    if (shape[0] < 0 || shape[1] < 0) fail<BooleanError>(doing, ": the child process's answer is damaged");
    Matrix m(shape[0], shape[1]);
    take(m.data(), sizeof(typename Matrix::Scalar) * static_cast<std::size_t>(m.size()), doing);
    return m;
  }

  void take(void* out, std::size_t size, const std::string& doing) {
    if (size > bytes.size() - at) fail<BooleanError>(doing, ": the child process's answer is cut short");
    if (size > 0) std::memcpy(out, bytes.data() + at, size);
    at += size;
  }
};

BooleanOutcome unpacked(const std::vector<char>& bytes, const std::string& doing) {
  if (bytes.empty()) fail<BooleanError>(doing, ": the child process gave no answer");
  const std::string message(bytes.begin() + 1, bytes.end());
  switch (bytes[0]) {
    case kInputError: fail<InputError>(message);
    case kBooleanError: fail<BooleanError>(message);
    case kOutOfMemory: fail<BooleanError>(doing, " ran out of memory");
    case kSolid: break;
    default: fail<BooleanError>(doing, ": the child process's answer is damaged");
  }
  if (bytes.size() < 2) fail<BooleanError>(doing, ": the child process's answer is cut short");
  Reader reader{bytes};
  BooleanOutcome outcome;
  outcome.changed = bytes[1] != 0;
  outcome.solid.vertices = reader.matrix<PointMatrix>(doing);
  outcome.solid.faces = reader.matrix<SimplexMatrix>(doing);
  return outcome;
}

}  // namespace

double boolean_time_limit(Index faces) { return 60.0 + 1e-3 * static_cast<double>(faces); }

BooleanOutcome isolated_boolean(const std::string& doing, const std::function<BooleanOutcome()>& work,
                                double time_limit_seconds, const Interrupter& interrupter) {
  interrupter.poll();
  std::vector<char> bytes;
  try {
    bytes = run_isolated(
        [&] {
          try {
            return packed(work());
          } catch (const InputError& e) {
            return packed_error(kInputError, e.what());
          } catch (const BooleanError& e) {
            return packed_error(kBooleanError, e.what());
          } catch (const std::bad_alloc&) {
            return packed_error(kOutOfMemory, "");
          }
        },
        time_limit_seconds, [&] { interrupter.poll(); });
  } catch (const IsolatedTimeout& e) {
    fail<TimeLimitError>("CGAL was stopped while ", doing, ": ", e.what(),
                         " (a Boolean of this size takes far less: CGAL loops on these operands)");
  } catch (const IsolatedFailure& e) {
    fail<BooleanError>("CGAL failed while ", doing, " (", e.what(), ")");
  }
  return unpacked(bytes, doing);
}

}  // namespace animanifold::holes
