#include "openmp_team_cap.hpp"

#include "animanifold/threads.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace animanifold {

namespace {

using Parallel = void (*)(void (*)(void*), void*, unsigned, unsigned);

std::atomic<std::int64_t> capped_count{0};

Parallel libgomp_parallel() {
  static const Parallel next = [] {
    void* symbol = dlsym(RTLD_NEXT, "GOMP_parallel");
    // Unreachable in practice: the core links libgomp, so the process cannot load without it.
    if (!symbol) {
      std::fprintf(stderr, "animanifold: no library after the core defines GOMP_parallel (libgomp missing)\n");
      std::abort();
    }
    return reinterpret_cast<Parallel>(symbol);
  }();
  return next;
}

}  // namespace

std::int64_t openmp_teams_capped() { return capped_count.load(std::memory_order_relaxed); }

}  // namespace animanifold

// libgomp's entry point for a parallel region (see openmp_team_cap.hpp).
// num_threads 0 asks for the calling thread's default (omp_set_num_threads),
// which a thread the core never set keeps at OpenMP's own default.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data,
                                                                     unsigned num_threads, unsigned flags) {
  const unsigned cap = static_cast<unsigned>(animanifold::thread_count());
  const unsigned asked = num_threads != 0 ? num_threads : static_cast<unsigned>(omp_get_max_threads());
  if (asked > cap) {
    num_threads = cap;
    animanifold::capped_count.fetch_add(1, std::memory_order_relaxed);
  }
  animanifold::libgomp_parallel()(fn, data, num_threads, flags);
}
