// Private: no OpenMP team started by the core or by the libraries it loads
// has more than thread_count() threads.
//
// Why: CHOLMOD 3.0 (SuiteSparse 5.12) runs a few OpenMP loops of its own in
// the supernodal factorisation (clearing a supernode, the row maps and the
// assembly of a descendant's update) with `num_threads(4)` compiled in
// (CHOLMOD_OMP_NUM_THREADS), which neither omp_set_num_threads nor any
// CHOLMOD setting reaches. On a 2-core machine those teams oversubscribe the
// cores and leave spinning threads behind that slow the tiled BLAS's own
// teams (tiled_blas.hpp): measured on the 102k-vertex manifold of
// bench/bench_laplacian.py, the factorisation took 8.2-9.3 s with teams of 4
// and 7.2-7.7 s with them capped at 2 threads. The rule that CHOLMOD,
// OpenBLAS and our loops agree on one thread count is kept here. The capped
// loops move each entry once, so the factor's bits do not depend on the cap.
//
// How: GCC compiles `#pragma omp parallel` into a call of libgomp's
// GOMP_parallel(fn, data, num_threads, flags); openmp_team_cap.cpp defines
// and exports that symbol, lowers a requested team above thread_count() to
// thread_count(), and forwards to libgomp's (dlsym(RTLD_NEXT)). Library
// imports bind to it as they bind to the tiled BLAS's symbols: in the Python
// module _core comes first in its dependencies' lookup scope, in a test
// executable the executable does. Where the process's global scope already
// holds libgomp (Debian's blender 3.4 binary links it), the libraries bind to
// libgomp directly and CHOLMOD's loops run on 4 threads: the same results,
// slower. openmp_teams_capped() tells the two apart.
#pragma once

#include <cstdint>

namespace animanifold {

// Outputs: how many OpenMP teams asked for more than thread_count() threads and
//   were given thread_count(), since the process started (an atomic read)
// Throws: nothing
std::int64_t openmp_teams_capped();

}  // namespace animanifold
