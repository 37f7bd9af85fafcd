// Private: CHOLMOD's supernodal factorisation and solves on every core, with
// the same bits for any thread count.
//
// Why: OpenBLAS's threaded kernels divide their work by the thread count, so
// a factor made on 2 threads differs in the last bits from one made on 1
// (threads.hpp). The BLAS calls CHOLMOD makes for large supernodes are cut
// here into tiles instead, whose bounds depend only on the call's sizes,
// never on the thread count (a solve's calls, with few right-hand sides,
// into row tiles: they are bound by reading the factor). Each tile is one
// call of the system BLAS on one thread, and the updates of a tile run in a
// fixed order, so the result is the tiling's, however many threads share the
// tiles (thread_count()).
//
// How CHOLMOD reaches it: libcholmod imports dgemm_, dsyrk_, dtrsm_ and
// dpotrf_, and tiled_blas.cpp defines and exports those four symbols. The
// dynamic linker binds libcholmod's imports to the first definition in its
// lookup scope: in the Python module that is _core itself (a module's
// dependencies come after it), in a test executable the executable. Each one
// tiles a call that is large enough and forwards every other call unchanged to
// the next definition (the system's BLAS and LAPACK, found with
// dlsym(RTLD_NEXT)). Where the process's global scope already holds a BLAS
// (Debian's blender 3.4 binary links libblas), CHOLMOD binds to that one and
// factorises on one thread, as before this layer: the same results up to the
// last bits, slower. tiled_blas_calls() tells the two apart.
#pragma once

#include <cstdint>

namespace animanifold {

// How many BLAS calls reached this layer since the process started.
struct TiledBlasCalls {
  std::int64_t tiled = 0;      // cut into tiles spread over thread_count() threads
  std::int64_t forwarded = 0;  // too small to gain from tiles: passed to the system BLAS as they came
};

// Outputs: the counts so far (atomic reads)
// Throws: nothing
TiledBlasCalls tiled_blas_calls();

// While one lives, BLAS calls from this thread run on it alone: OpenBLAS's
// OpenMP build sizes a call's team by the calling thread's
// omp_get_max_threads() (outside a parallel region), which this sets to 1
// and restores. Each tiled entry point holds one, so that every system call,
// on a tile or forwarded, runs on the thread that makes it; SparseCholesky
// holds one around CHOLMOD's solves.
class OneBlasThread {
 public:
  OneBlasThread();
  ~OneBlasThread();
  OneBlasThread(const OneBlasThread&) = delete;
  OneBlasThread& operator=(const OneBlasThread&) = delete;

 private:
  int before_;
};

// The tile edge of every tiled call, in rows and columns: large enough that
// each tile runs the system BLAS near its serial peak and the tiles need few
// barriers, small enough that the largest supernodes of a Laplacian in R^4
// (thousands of columns) give both cores work until the last tiles. Measured
// on the 102k-vertex manifold of bench/bench_laplacian.py (2 threads, calls
// under 128·T² flops forwarded), the factorisation took 9.0-9.7 s with T = 256,
// 8.4-8.6 s with 384 and 8.0-8.1 s with 512 (one thread, untiled: 11.4 s).
constexpr int kBlasTile = 512;

}  // namespace animanifold
