#include "animanifold/threads.hpp"

#include "animanifold/errors.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <atomic>

namespace animanifold {

namespace {

// 0 until the first read or write: then OpenMP's default at that time.
std::atomic<int> configured{0};

// OpenBLAS's own setter, when the process's BLAS is OpenBLAS (looked up,
// not linked: CHOLMOD brings whichever BLAS the system's alternative names).
void set_openblas_threads(int count) {
  using Setter = void (*)(int);
  static const Setter setter = reinterpret_cast<Setter>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (setter) setter(count);
}

int openblas_threads() {
  using Getter = int (*)();
  static const Getter getter = reinterpret_cast<Getter>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return getter ? getter() : 0;
}

}  // namespace

int set_thread_count(int count) {
  if (count < 0) fail<InputError>("thread count must be >= 1, or 0 for every core; got ", count);
  // Far more threads than any machine has cores would only exhaust memory on thread stacks.
  if (count > kMaxThreads) fail<InputError>("thread count ", count, " is more than ", kMaxThreads);
  const int resolved = count == 0 ? omp_get_num_procs() : count;
  configured.store(resolved);
  set_openblas_threads(resolved);
  apply_thread_count();
  return resolved;
}

int thread_count() {
  int count = configured.load();
  if (count == 0) {
    int expected = 0;
    configured.compare_exchange_strong(expected, omp_get_max_threads());
    count = configured.load();
  }
  return count;
}

void apply_thread_count() {
  const int count = thread_count();
  if (omp_get_max_threads() != count) omp_set_num_threads(count);
}

int parallel_team_size() {
  int size = 0;
#pragma omp parallel num_threads(thread_count())
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  return size;
}

int blas_thread_count() {
  apply_thread_count();
  return openblas_threads();
}

}  // namespace animanifold
