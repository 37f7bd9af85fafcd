// Private: a thin RAII wrapper over CHOLMOD's supernodal Cholesky, used by the
// Deformer (factor LᵀL once, solve all coordinates as one multi-column
// right-hand side, one cholmod_solve for x, y, z and t), its BLAS by tiles of
// fixed size, one thread per tile (same bits for any thread count:
// tiled_blas.hpp). Kept
// out of the public headers so that nothing outside cpp/src needs cholmod.h.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>

namespace animanifold {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  // Factors the symmetric matrix whose lower triangle is `lower` (compressed,
  // column-major). Returns false when CHOLMOD finds it not positive definite.
  bool factor(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& lower);
  // CHOLMOD's cheap reciprocal condition estimate, (min diag L / max diag L)².
  double rcond() const;
  std::int64_t factor_nonzeros() const;
  // Floating-point operations of the last factorisation (CHOLMOD's count).
  double factor_flops() const;
  // Seconds the last factor() spent choosing the ordering (cholmod_analyze)
  // and computing the numbers (cholmod_factorize): for reports only.
  double analyse_seconds() const;
  double factorise_seconds() const;
  // BLAS calls of the last factor() that ran by tiles on thread_count()
  // threads (tiled_blas.hpp): 0 for a small matrix, or in a process where
  // CHOLMOD binds to another BLAS.
  std::int64_t tiled_blas_calls() const;
  // OpenMP teams of the last factor() that asked for more than thread_count()
  // threads and got thread_count() (openmp_team_cap.hpp).
  std::int64_t openmp_teams_capped() const;
  // Solves A X = B for all columns of B at once.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace animanifold
