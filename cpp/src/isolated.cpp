// run_isolated (isolated.hpp): fork, a pipe, poll and waitpid.
#include "animanifold/isolated.hpp"

#include "animanifold/threads.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <poll.h>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <string>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace animanifold {

namespace {

// The child's message: one tag byte ('R' result, 'E' error message), then the
// payload's length and the payload.
constexpr char kResult = 'R', kError = 'E';

bool write_all(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

[[noreturn]] void send_and_exit(int fd, char tag, const char* data, size_t size) {
  const std::uint64_t length = size;
  const bool sent = write_all(fd, &tag, 1) && write_all(fd, reinterpret_cast<const char*>(&length), sizeof length) &&
                    write_all(fd, data, size);
  // _exit, not exit: the child must not run the parent's atexit handlers or
  // flush its buffers (Python's, Blender's) a second time.
  ::_exit(sent ? 0 : 3);
}

std::string signal_name(int signal) {
  switch (signal) {
    case SIGABRT: return "SIGABRT, an assertion failed or abort() was called";
    case SIGSEGV: return "SIGSEGV, a segmentation fault";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGKILL: return "SIGKILL, killed (out of memory?)";
    default: return "signal " + std::to_string(signal);
  }
}

// The crash handlers the parent installed (Blender's crash log, Python's faulthandler, a
// fuzzer's or a sanitizer's report) are not the child's to run: a crash of the library in
// the child must end it by its signal, which the parent reads and reports, without writing
// the parent's crash files or messages.
void restore_default_crash_handlers() {
  for (int signal : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(signal, SIG_DFL);
}

// What the library prints on the way (TetGen's "Found two facets intersect each other" and
// the like) is not for the user's console: the child's failure comes back as our message.
// No flush first: what stdout's buffer holds is the parent's, and the parent writes it.
void silence_standard_output() {
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::close(null);
  }
}

// One fork at a time in this process. Libraries' fork handlers are not
// written for two forks at once: scipy's OpenBLAS, loaded beside us, shuts
// its thread pool down before every fork, and two such shutdowns together
// join its threads twice and wait for ever. The field morph meshes its two
// ends side by side, each in a child process.
std::mutex& fork_lock() {
  static std::mutex lock;
  return lock;
}

}  // namespace

std::vector<char> run_isolated(const std::function<std::vector<char>()>& work, double timeout_seconds,
                               const std::function<void()>& while_waiting) {
#ifdef __SANITIZE_THREAD__
  // ThreadSanitizer's runtime keeps a thread of its own, whose locks a forked
  // child can inherit held and then wait on for ever: in such a build (CI's
  // tsan. tests, whose inputs never end their process) the work stays here.
  return work();
#endif
  int fds[2];
  if (::pipe(fds) != 0) return work();
  pid_t pid;
  {
    const std::lock_guard<std::mutex> one_at_a_time(fork_lock());
    pid = ::fork();
  }
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return work();
  }
  if (pid == 0) {  // the child
    ::close(fds[0]);
    restore_default_crash_handlers();
    silence_standard_output();
    // The parent's OpenMP threads do not exist in the child, and libgomp would
    // wait for ever on a team that reuses them: the child's loops run on its
    // one thread (their results do not depend on the count).
    set_thread_count(1);
    try {
      const std::vector<char> result = work();
      send_and_exit(fds[1], kResult, result.data(), result.size());
    } catch (const std::exception& e) {
      send_and_exit(fds[1], kError, e.what(), std::strlen(e.what()));
    } catch (...) {
      static const char unknown[] = "an exception that is not a std::exception";
      send_and_exit(fds[1], kError, unknown, sizeof unknown - 1);
    }
  }
  ::close(fds[1]);
  std::vector<char> message;
  char buffer[1 << 16];
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  bool timed_out = false;
  // The child is stopped and reaped before anything leaves this function.
  auto stop_child = [&] {
    ::kill(pid, SIGKILL);
    ::close(fds[0]);
    int ignored = 0;
    while (::waitpid(pid, &ignored, 0) < 0 && errno == EINTR) {
    }
  };
  for (;;) {  // read to the end before waiting: a full pipe would block the child
    if (timeout_seconds > 0 || while_waiting) {
      const double left = timeout_seconds > 0
                              ? std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count()
                              : kWaitTick;
      const double wait = while_waiting ? std::min(left, kWaitTick) : left;
      pollfd readable{fds[0], POLLIN, 0};
      const int ready = wait > 0 ? ::poll(&readable, 1, static_cast<int>(std::min(wait * 1000.0 + 1.0, 2.0e9))) : 0;
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0 && left <= wait && timeout_seconds > 0) {
        timed_out = true;
        ::kill(pid, SIGKILL);
        break;
      }
      if (ready == 0) {  // still running: the caller's turn
        if (while_waiting) {
          try {
            while_waiting();
          } catch (...) {
            stop_child();
            throw;
          }
        }
        continue;
      }
    }
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    message.insert(message.end(), buffer, buffer + n);
  }
  ::close(fds[0]);
  int status = 0;
  pid_t waited;
  do waited = ::waitpid(pid, &status, 0);
  while (waited < 0 && errno == EINTR);
  if (timed_out)
    throw IsolatedTimeout("it did not finish within " + std::to_string(static_cast<long>(timeout_seconds)) +
                          " s and was stopped");
  // (Where the host ignores SIGCHLD, children are reaped on their own and
  // waitpid fails with ECHILD: the message alone then says how it went.)
  if (waited == pid && WIFSIGNALED(status))
    throw IsolatedFailure("it was killed by " + signal_name(WTERMSIG(status)));
  std::uint64_t length = 0;
  const size_t header = 1 + sizeof length;
  if (message.size() >= header) std::memcpy(&length, message.data() + 1, sizeof length);
  if (message.size() < header || message.size() - header != length) {
    if (waited == pid && WIFEXITED(status))
      throw IsolatedFailure("it exited with status " + std::to_string(WEXITSTATUS(status)) + " before finishing");
    throw IsolatedFailure("it ended before finishing");
  }
  std::vector<char> payload(message.begin() + static_cast<std::ptrdiff_t>(header), message.end());
  if (message[0] == kError) throw IsolatedFailure(std::string(payload.begin(), payload.end()));
  return payload;
}

}  // namespace animanifold
