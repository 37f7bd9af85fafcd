// How many threads the core's parallel work uses: one setting for our own
// loops, for OpenBLAS under CHOLMOD, and for what CHOLMOD itself runs.
//
// We chose OpenMP (already linked for the distance queries and frame checks)
// over oneTBB: one threading runtime in the process, so the loops here and
// the BLAS below CHOLMOD share one pool and one count and never oversubscribe
// the cores (inside Blender, the count defaults to Blender's own setting;
// the add-on's preferences.py applies it).
//
// - Our loops: every `#pragma omp parallel` asks for thread_count() threads
//   (`num_threads(thread_count())`), whichever thread calls the core (a
//   Python worker thread of am.CoreJob as much as the main one).
// - OpenBLAS: the system BLAS is Debian's OpenMP build (libopenblas0-openmp,
//   scripts/install-deps.sh). That build sizes each BLAS call's team by the
//   calling thread's omp_get_max_threads(), which apply_thread_count() sets;
//   set_thread_count() also calls openblas_set_num_threads (found with dlsym,
//   so a reference BLAS without it is fine). One count, one OpenMP pool:
//   BLAS never runs a team of its own beside ours.
// - CHOLMOD: SuiteSparse 5.12's CHOLMOD 3.0 has no thread setting of its own
//   (cholmod_common gained nthreads_max only in CHOLMOD 4); its supernodal
//   factorisation spends its time in BLAS (dsyrk, dgemm, dpotrf, dtrsm).
//   OpenBLAS 0.3.21's threaded dpotrf blocks its work by the thread count,
//   and so, measured on the Laplacian's normal matrix, do its threaded dgemm,
//   dsyrk and dtrsm: a factor made with any one of the four on 2 threads
//   (the other three on 1) differs in the last bits from one made on 1, so
//   keeping only dpotrf serial is not enough. SparseCholesky therefore runs
//   OpenBLAS on the calling thread alone (sparse_cholesky.cpp), and the large
//   calls of the factorisation are cut into tiles of fixed size spread over
//   thread_count() threads (cpp/src/tiled_blas.hpp), so the Laplacian uses
//   every core and gives the same bits for any count. CHOLMOD's
//   OpenMP loops of its own (clearing supernodes, row maps, the assembly of
//   updates) ask for a team of CHOLMOD_OMP_NUM_THREADS = 4 compiled into the
//   library, which no setting reaches: the core caps every OpenMP team at
//   thread_count() where it is requested (cpp/src/openmp_team_cap.hpp).
//   Those loops move each value once, so the cap does not change the bits.
//
// Every parallel loop of the core writes each item's result to that item's
// own slot (precomputed offsets), and no loop reduces floating-point values
// across threads, so results are bit for bit the same for any thread count
// (tests/test_thread_count.py compares 1 and 2 threads).
#pragma once

namespace animanifold {

// The most threads set_thread_count() accepts.
constexpr int kMaxThreads = 1024;

// Inputs:
//   count  threads for the core's parallel work: >= 1, or 0 for every core
//          (omp_get_num_procs())
// Outputs:
//   the count now in use (count, or the number of cores for 0); it also applies to
//   OpenBLAS (openblas_set_num_threads) and to the calling thread (apply_thread_count)
// Throws: InputError naming the count when it is negative or above kMaxThreads; the
//   count in use is then unchanged
int set_thread_count(int count);

// Outputs: the threads the core's parallel work uses: the last set_thread_count()'s,
//   else OpenMP's default when first asked (OMP_NUM_THREADS, else every core), kept
//   from then on
// Throws: nothing
int thread_count();

// Outputs: the calling thread's OpenMP setting (omp_set_num_threads, and so the team
//   size of a BLAS call it makes) is thread_count()
// Throws: nothing
//
// OpenMP keeps that setting per thread and the caller may be any thread, so
// code that calls BLAS for a parallel result calls this first (the
// Laplacian's CHOLMOD calls deliberately run BLAS on one thread instead: see
// above).
void apply_thread_count();

// Outputs: the team size a core loop gets, as omp_get_num_threads() reports inside a
//   `num_threads(thread_count())` region (for the tests)
// Throws: nothing
int parallel_team_size();

// Outputs: OpenBLAS's thread count after apply_thread_count() on the calling thread,
//   or 0 when the process's BLAS is not OpenBLAS (for the tests)
// Throws: nothing
int blas_thread_count();

}  // namespace animanifold
