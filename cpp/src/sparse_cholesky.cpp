#include "sparse_cholesky.hpp"

#include "animanifold/errors.hpp"
#include "openmp_team_cap.hpp"
#include "tiled_blas.hpp"

#include <cholmod.h>
#include <chrono>
#include <cstring>

namespace animanifold {

// OpenBLAS's threaded kernels split some sums by the thread count (dpotrf,
// dgemm, dsyrk and dtrsm each change the factor's last bits on 2 threads, see
// threads.hpp), so CHOLMOD's calls run BLAS on the calling thread alone
// (OneBlasThread). The large calls of the factorisation and of the solves
// still use every core: they reach the tiled layer of tiled_blas.hpp, whose
// tiles do not depend on the thread count. So the Laplacian gives the same
// bits for any thread count. CHOLMOD's own OpenMP loops, which ask for 4
// threads whatever the setting, are held to thread_count() too
// (openmp_team_cap.hpp).

struct SparseCholesky::Impl {
  // cholmod_common is used by const solves too (workspace, status): mutable.
  mutable cholmod_common common;
  cholmod_factor* factor = nullptr;
  Eigen::Index n = 0;
  double analyse_seconds = 0, factorise_seconds = 0;
  std::int64_t tiled_calls = 0, teams_capped = 0;

  Impl() {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.print = 0;  // failures are reported through our return values, not stderr
    // Supernodes of up to 16 columns are merged whatever the zeros they add,
    // up to 64 and 128 when few are added (CHOLMOD's defaults: 4, 16, 48).
    // A surface's normal matrix has many small supernodes, where serial BLAS
    // runs far below its peak: merging them factors the 94k-vertex surface of
    // bench/bench_laplacian.py 10-15 % faster; the large supernodes of a
    // manifold in R^4 are not affected.
    common.nrelax[0] = 16, common.nrelax[1] = 64, common.nrelax[2] = 128;
  }
  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::factor(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& lower) {
  Impl& d = *impl_;
  if (!lower.isCompressed()) fail<InputError>("SparseCholesky: matrix must be compressed");
  const OneBlasThread one_blas_thread;
  if (d.factor) cholmod_free_factor(&d.factor, &d.common);
  cholmod_sparse A;
  std::memset(&A, 0, sizeof A);
  A.nrow = static_cast<size_t>(lower.rows());
  A.ncol = static_cast<size_t>(lower.cols());
  A.nzmax = static_cast<size_t>(lower.nonZeros());
  A.p = const_cast<int*>(lower.outerIndexPtr());
  A.i = const_cast<int*>(lower.innerIndexPtr());
  A.x = const_cast<double*>(lower.valuePtr());
  A.stype = -1;  // lower triangle of a symmetric matrix
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  d.n = lower.rows();
  using Clock = std::chrono::steady_clock;
  const std::int64_t tiled_before = animanifold::tiled_blas_calls().tiled;
  const std::int64_t capped_before = animanifold::openmp_teams_capped();
  const auto start = Clock::now();
  d.factor = cholmod_analyze(&A, &d.common);
  if (!d.factor) fail<MeshingError>("CHOLMOD could not analyse the normal matrix (status ", d.common.status, ")");
  const auto analysed = Clock::now();
  cholmod_factorize(&A, d.factor, &d.common);
  d.analyse_seconds = std::chrono::duration<double>(analysed - start).count();
  d.factorise_seconds = std::chrono::duration<double>(Clock::now() - analysed).count();
  d.tiled_calls = animanifold::tiled_blas_calls().tiled - tiled_before;
  d.teams_capped = animanifold::openmp_teams_capped() - capped_before;
  if (d.common.status == CHOLMOD_NOT_POSDEF || d.factor->minor < d.factor->n) return false;
  if (d.common.status < CHOLMOD_OK)
    fail<MeshingError>("CHOLMOD failed to factor the normal matrix (status ", d.common.status, ")");
  return true;
}

double SparseCholesky::rcond() const {
  if (!impl_->factor) return 0;
  return cholmod_rcond(impl_->factor, &impl_->common);
}

std::int64_t SparseCholesky::factor_nonzeros() const {
  return impl_->factor ? static_cast<std::int64_t>(impl_->common.lnz) : 0;
}

double SparseCholesky::factor_flops() const { return impl_->factor ? impl_->common.fl : 0; }
std::int64_t SparseCholesky::tiled_blas_calls() const { return impl_->tiled_calls; }
std::int64_t SparseCholesky::openmp_teams_capped() const { return impl_->teams_capped; }
double SparseCholesky::analyse_seconds() const { return impl_->analyse_seconds; }
double SparseCholesky::factorise_seconds() const { return impl_->factorise_seconds; }

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
  const Impl& d = *impl_;
  if (!d.factor) fail<MeshingError>("SparseCholesky: solve before factor");
  if (B.rows() != d.n) fail<InputError>("SparseCholesky: right-hand side has ", B.rows(), " rows for ", d.n);
  const OneBlasThread one_blas_thread;
  cholmod_dense b;
  std::memset(&b, 0, sizeof b);
  b.nrow = static_cast<size_t>(B.rows());
  b.ncol = static_cast<size_t>(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(B.data());
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, d.factor, &b, &d.common);
  if (!x) fail<MeshingError>("CHOLMOD solve failed (status ", d.common.status, ")");
  Eigen::MatrixXd X = Eigen::Map<const Eigen::MatrixXd>(static_cast<double*>(x->x), B.rows(), B.cols());
  cholmod_free_dense(&x, &d.common);
  return X;
}

}  // namespace animanifold
