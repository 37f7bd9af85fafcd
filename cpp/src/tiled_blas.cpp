#include "tiled_blas.hpp"

#include "animanifold/threads.hpp"

#include <dlfcn.h>
#include <omp.h>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

namespace animanifold {

namespace {

// The Fortran signatures CHOLMOD calls (no hidden string lengths: CHOLMOD's
// own prototypes have none, so neither do the calls it makes to us).
using Gemm = void (*)(const char*, const char*, const int*, const int*, const int*, const double*, const double*,
                      const int*, const double*, const int*, const double*, double*, const int*);
using Syrk = void (*)(const char*, const char*, const int*, const int*, const double*, const double*, const int*,
                      const double*, double*, const int*);
using Trsm = void (*)(const char*, const char*, const char*, const char*, const int*, const int*, const double*,
                      const double*, const int*, double*, const int*);
using Potrf = void (*)(const char*, const int*, double*, const int*, int*);

template <class Function>
Function next_definition(const char* name) {
  void* symbol = dlsym(RTLD_NEXT, name);
  // Unreachable in practice: libcholmod, which the core links, cannot load without it.
  if (!symbol) {
    std::fprintf(stderr, "animanifold: no library after the core defines %s (BLAS/LAPACK missing)\n", name);
    std::abort();
  }
  return reinterpret_cast<Function>(symbol);
}

struct SystemBlas {
  Gemm gemm = next_definition<Gemm>("dgemm_");
  Syrk syrk = next_definition<Syrk>("dsyrk_");
  Trsm trsm = next_definition<Trsm>("dtrsm_");
  Potrf potrf = next_definition<Potrf>("dpotrf_");
};

const SystemBlas& system_blas() {
  static const SystemBlas blas;
  return blas;
}

std::atomic<std::int64_t> tiled_count{0}, forwarded_count{0};

// Calls below this many flops run as they came: a tile's call overhead, the
// lost packing reuse and the barrier cost more than a second core gains. On
// the 102k-vertex manifold of bench/bench_laplacian.py (2 threads) the
// factorisation took 9.3-10.0 s with 8e6, 8.6-8.7 s with 3.4e7, 8.2-8.8 s
// with 1e8 and 8.2-8.5 s with 3e8.
constexpr double kMinTiledFlops = 1.0e8;

bool is(const char* flag, char letter) { return std::toupper(static_cast<unsigned char>(*flag)) == letter; }

int tiles_along(int extent) { return (extent + kBlasTile - 1) / kBlasTile; }
int tile_extent(int extent, int tile) { return std::min(kBlasTile, extent - tile * kBlasTile); }

// Runs work(0..items-1) on thread_count() threads. Each item writes only its
// own tile, so the order the threads take them in cannot change a bit.
template <class Work>
void for_each_tile(int items, const Work& work) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
  for (int item = 0; item < items; ++item) work(item);
}

// Tile (row, column) pairs of the lower triangle of a grid of `tiles` x `tiles`.
std::vector<std::pair<int, int>> lower_tiles(int tiles) {
  std::vector<std::pair<int, int>> pairs;
  for (int column = 0; column < tiles; ++column)
    for (int row = column; row < tiles; ++row) pairs.emplace_back(row, column);
  return pairs;
}

// C = alpha op(A) op(B) + beta C, by tiles of C.
void tiled_gemm(const char* transa, const char* transb, int m, int n, int k, double alpha, const double* A, int lda,
                const double* B, int ldb, double beta, double* C, int ldc) {
  const int row_tiles = tiles_along(m), column_tiles = tiles_along(n);
  for_each_tile(row_tiles * column_tiles, [&](int item) {
    const int row = item % row_tiles, column = item / row_tiles;
    const int i0 = row * kBlasTile, j0 = column * kBlasTile;
    const int mb = tile_extent(m, row), nb = tile_extent(n, column);
    const double* a = is(transa, 'N') ? A + i0 : A + static_cast<std::ptrdiff_t>(i0) * lda;
    const double* b = is(transb, 'N') ? B + static_cast<std::ptrdiff_t>(j0) * ldb : B + j0;
    system_blas().gemm(transa, transb, &mb, &nb, &k, &alpha, a, &lda, b, &ldb, &beta,
                       C + i0 + static_cast<std::ptrdiff_t>(j0) * ldc, &ldc);
  });
}

// The lower triangle of C = alpha op(A) op(A)ᵀ + beta C, by tiles of C: the
// diagonal tiles by syrk, the others by gemm.
void tiled_syrk_lower(const char* trans, int n, int k, double alpha, const double* A, int lda, double beta, double* C,
                      int ldc) {
  const bool plain = is(trans, 'N');
  const std::vector<std::pair<int, int>> tiles = lower_tiles(tiles_along(n));
  for_each_tile(static_cast<int>(tiles.size()), [&](int item) {
    const auto [row, column] = tiles[item];
    const int i0 = row * kBlasTile, j0 = column * kBlasTile;
    const int mb = tile_extent(n, row), nb = tile_extent(n, column);
    const double* a_rows = plain ? A + i0 : A + static_cast<std::ptrdiff_t>(i0) * lda;
    const double* a_columns = plain ? A + j0 : A + static_cast<std::ptrdiff_t>(j0) * lda;
    double* c = C + i0 + static_cast<std::ptrdiff_t>(j0) * ldc;
    if (row == column) system_blas().syrk("L", trans, &nb, &k, &alpha, a_columns, &lda, &beta, c, &ldc);
    else system_blas().gemm(plain ? "N" : "T", plain ? "T" : "N", &mb, &nb, &k, &alpha, a_rows, &lda, a_columns, &lda,
                            &beta, c, &ldc);
  });
}

// op(A) X = alpha B (side L) or X op(A) = alpha B (side R), B overwritten
// by X: the columns (side L) or rows (side R) of B are independent systems.
void tiled_trsm(const char* side, const char* uplo, const char* transa, const char* diag, int m, int n, double alpha,
                const double* A, int lda, double* B, int ldb) {
  const bool left = is(side, 'L');
  for_each_tile(tiles_along(left ? n : m), [&](int tile) {
    const int start = tile * kBlasTile;
    const int rows = left ? m : tile_extent(m, tile), columns = left ? tile_extent(n, tile) : n;
    double* b = left ? B + static_cast<std::ptrdiff_t>(start) * ldb : B + start;
    system_blas().trsm(side, uplo, transa, diag, &rows, &columns, &alpha, A, &lda, b, &ldb);
  });
}

// op(L) X = B for a lower-triangular L of many rows and a B of few columns
// (CHOLMOD's solves): a blocked substitution over row tiles of L. Each step
// solves one diagonal tile, then subtracts its part from the tiles still to
// come, one tile per thread; each tile takes those updates in step order.
// Forward (op(L) = L) runs the tiles down, backward (op(L) = Lᵀ) up.
void tiled_substitution(const char* transa, const char* diag, int m, int n, double alpha, const double* L, int lda,
                        double* B, int ldb) {
  const auto at = [&](int row, int column) { return L + row + static_cast<std::ptrdiff_t>(column) * lda; };
  const auto rows_of = [&](int tile) { return B + tile * kBlasTile; };
  const int tiles = tiles_along(m);
  const double one = 1, minus_one = -1;
  if (alpha != 1)
    for_each_tile(n, [&](int column) {
      for (int row = 0; row < m; ++row) B[row + static_cast<std::ptrdiff_t>(column) * ldb] *= alpha;
    });
  const bool forward = is(transa, 'N');
  for (int done = 0; done < tiles; ++done) {
    const int step = forward ? done : tiles - 1 - done, k0 = step * kBlasTile, kb = tile_extent(m, step);
    system_blas().trsm("L", "L", transa, diag, &kb, &n, &one, at(k0, k0), &lda, rows_of(step), &ldb);
    const int remaining = tiles - 1 - done;
    for_each_tile(remaining, [&](int item) {
      const int tile = forward ? step + 1 + item : item, i0 = tile * kBlasTile, ib = tile_extent(m, tile);
      if (forward)  // B_i -= L_ij X_j
        system_blas().gemm("N", "N", &ib, &n, &kb, &minus_one, at(i0, k0), &lda, rows_of(step), &ldb, &one,
                           rows_of(tile), &ldb);
      else  // B_i -= L_jiᵀ X_j
        system_blas().gemm("T", "N", &ib, &n, &kb, &minus_one, at(k0, i0), &lda, rows_of(step), &ldb, &one,
                           rows_of(tile), &ldb);
    });
  }
}

// Right-looking Cholesky A = L Lᵀ of the lower triangle by tiles: factor the
// diagonal tile, solve the tiles below it, update the trailing tiles; each
// trailing tile takes its updates in the order of the steps.
int tiled_potrf_lower(int n, double* A, int lda) {
  const auto at = [&](int row, int column) { return A + row + static_cast<std::ptrdiff_t>(column) * lda; };
  const int tiles = tiles_along(n);
  const double one = 1, minus_one = -1;
  for (int step = 0; step < tiles; ++step) {
    const int k0 = step * kBlasTile, kb = tile_extent(n, step);
    int info = 0;
    system_blas().potrf("L", &kb, at(k0, k0), &lda, &info);
    if (info != 0) return info > 0 ? k0 + info : info;
    for_each_tile(tiles - step - 1, [&](int below) {
      const int row = step + 1 + below, rows = tile_extent(n, row);
      system_blas().trsm("R", "L", "T", "N", &rows, &kb, &one, at(k0, k0), &lda, at(row * kBlasTile, k0), &lda);
    });
    std::vector<std::pair<int, int>> trailing = lower_tiles(tiles - step - 1);
    for_each_tile(static_cast<int>(trailing.size()), [&](int item) {
      const int row = step + 1 + trailing[item].first, column = step + 1 + trailing[item].second;
      const int i0 = row * kBlasTile, j0 = column * kBlasTile;
      const int mb = tile_extent(n, row), nb = tile_extent(n, column);
      if (row == column)
        system_blas().syrk("L", "N", &nb, &kb, &minus_one, at(j0, k0), &lda, &one, at(j0, j0), &lda);
      else
        system_blas().gemm("N", "T", &mb, &nb, &kb, &minus_one, at(i0, k0), &lda, at(j0, k0), &lda, &one, at(i0, j0),
                           &lda);
    });
  }
  return 0;
}

// Whether a call of `flops` over a tile grid of `tiles` tiles is cut up.
bool worth_tiling(double flops, int tiles) { return tiles > 1 && flops >= kMinTiledFlops; }

// A call with at most this many right-hand-side columns (a solve's) streams
// its matrix through once: its time is the bytes it reads, not its flops.
constexpr int kStreamingColumns = 16;
// Streaming calls whose matrix is at least this many entries (2 MiB) are cut
// into row tiles, so that both cores read it. On the 102k-vertex manifold of
// bench/bench_laplacian.py a fresh solve (4 columns) took 0.27 s on one
// thread, 0.22-0.27 s on two with 8 MiB and 0.21-0.22 s with 2 MiB: OpenBLAS
// packs each tile of the factor before using it, so the solve stays far from
// reading the factor at the machine's bandwidth.
constexpr double kMinStreamedEntries = 1 << 18;

bool worth_streaming(int columns, double matrix_entries, int row_tiles) {
  return columns <= kStreamingColumns && row_tiles > 1 && matrix_entries >= kMinStreamedEntries;
}

bool count(bool tiled) {
  (tiled ? tiled_count : forwarded_count).fetch_add(1, std::memory_order_relaxed);
  return tiled;
}

}  // namespace

OneBlasThread::OneBlasThread() : before_(omp_get_max_threads()) {
  // thread_count() takes OpenMP's default when first asked: ask it before
  // this thread's setting drops to 1, or a first ask below (a tile loop, a
  // team held by openmp_team_cap) would keep 1 for the whole process.
  thread_count();
  omp_set_num_threads(1);
}
OneBlasThread::~OneBlasThread() { omp_set_num_threads(before_); }

TiledBlasCalls tiled_blas_calls() {
  return {tiled_count.load(std::memory_order_relaxed), forwarded_count.load(std::memory_order_relaxed)};
}

}  // namespace animanifold

// The exported BLAS and LAPACK entry points (see tiled_blas.hpp).
using namespace animanifold;

extern "C" __attribute__((visibility("default"))) void dgemm_(const char* transa, const char* transb, const int* m,
                                                              const int* n, const int* k, const double* alpha,
                                                              const double* A, const int* lda, const double* B,
                                                              const int* ldb, const double* beta, double* C,
                                                              const int* ldc) {
  const OneBlasThread one_blas_thread;
  if (count(worth_tiling(2.0 * *m * *n * *k, tiles_along(*m) * tiles_along(*n)) ||
            worth_streaming(*n, 1.0 * *m * *k, tiles_along(*m))))
    tiled_gemm(transa, transb, *m, *n, *k, *alpha, A, *lda, B, *ldb, *beta, C, *ldc);
  else
    system_blas().gemm(transa, transb, m, n, k, alpha, A, lda, B, ldb, beta, C, ldc);
}

extern "C" __attribute__((visibility("default"))) void dsyrk_(const char* uplo, const char* trans, const int* n,
                                                              const int* k, const double* alpha, const double* A,
                                                              const int* lda, const double* beta, double* C,
                                                              const int* ldc) {
  const OneBlasThread one_blas_thread;
  if (count(is(uplo, 'L') && worth_tiling(1.0 * *n * *n * *k, tiles_along(*n))))
    tiled_syrk_lower(trans, *n, *k, *alpha, A, *lda, *beta, C, *ldc);
  else
    system_blas().syrk(uplo, trans, n, k, alpha, A, lda, beta, C, ldc);
}

extern "C" __attribute__((visibility("default"))) void dtrsm_(const char* side, const char* uplo, const char* transa,
                                                              const char* diag, const int* m, const int* n,
                                                              const double* alpha, const double* A, const int* lda,
                                                              double* B, const int* ldb) {
  const OneBlasThread one_blas_thread;
  const bool left = is(side, 'L');
  const double flops = left ? 1.0 * *m * *m * *n : 1.0 * *m * *n * *n;
  const bool substitution = left && is(uplo, 'L') && worth_streaming(*n, 0.5 * *m * *m, tiles_along(*m));
  const bool tiled = !substitution && worth_tiling(flops, tiles_along(left ? *n : *m));
  count(substitution || tiled);
  if (substitution)
    tiled_substitution(transa, diag, *m, *n, *alpha, A, *lda, B, *ldb);
  else if (tiled)
    tiled_trsm(side, uplo, transa, diag, *m, *n, *alpha, A, *lda, B, *ldb);
  else
    system_blas().trsm(side, uplo, transa, diag, m, n, alpha, A, lda, B, ldb);
}

extern "C" __attribute__((visibility("default"))) void dpotrf_(const char* uplo, const int* n, double* A,
                                                               const int* lda, int* info) {
  const OneBlasThread one_blas_thread;
  if (count(is(uplo, 'L') && worth_tiling(1.0 * *n * *n * *n / 3, tiles_along(*n))))
    *info = tiled_potrf_lower(*n, A, *lda);
  else
    system_blas().potrf(uplo, n, A, lda, info);
}
