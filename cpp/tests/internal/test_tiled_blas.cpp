// The tiled BLAS layer under CHOLMOD (tiled_blas.hpp): each of its four entry
// points gives the operation's answer, the same bits on 1 and 2 threads, and
// takes the tiled path only for calls large enough; dpotrf reports the first
// column that is not positive definite, counted over the whole matrix.
#include "tiled_blas.hpp"

#include "animanifold/threads.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

extern "C" {
void dgemm_(const char*, const char*, const int*, const int*, const int*, const double*, const double*, const int*,
            const double*, const int*, const double*, double*, const int*);
void dsyrk_(const char*, const char*, const int*, const int*, const double*, const double*, const int*, const double*,
            double*, const int*);
void dtrsm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
void dpotrf_(const char*, const int*, double*, const int*, int*);
}

using namespace animanifold;

namespace {

Eigen::MatrixXd random_matrix(int rows, int columns, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::MatrixXd M(rows, columns);
  for (int c = 0; c < columns; ++c)
    for (int r = 0; r < rows; ++r) M(r, c) = uniform(generator);
  return M;
}

Eigen::MatrixXd positive_definite(int n, unsigned seed) {
  const Eigen::MatrixXd B = random_matrix(n, n, seed);
  return B * B.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

// Runs `call` (which fills its result from the same inputs each time) on 1
// and on 2 threads, expects bit-equal results and that it took the tiled
// path `tiled` times per run; returns the result.
Eigen::MatrixXd same_on_one_and_two_threads(const std::function<Eigen::MatrixXd()>& call, int tiled) {
  const int before = thread_count();
  set_thread_count(1);
  const std::int64_t start = tiled_blas_calls().tiled;
  const Eigen::MatrixXd one = call();
  EXPECT_EQ(tiled_blas_calls().tiled - start, tiled);
  set_thread_count(2);
  const Eigen::MatrixXd two = call();
  set_thread_count(before);
  EXPECT_EQ(tiled_blas_calls().tiled - start, 2 * tiled);
  EXPECT_EQ(one.rows(), two.rows());
  EXPECT_TRUE(one == two) << "the result changed with the thread count";
  return one;
}

}  // namespace

TEST(TiledBlas, GemmGivesTheProductForEveryTransposition) {
  const int m = 700, n = 600, k = 300;  // more than one tile along m and n, with remainders
  for (const char* transa : {"N", "T"})
    for (const char* transb : {"N", "T"}) {
      const bool ta = *transa == 'T', tb = *transb == 'T';
      const Eigen::MatrixXd A = random_matrix(ta ? k : m, ta ? m : k, 1), B = random_matrix(tb ? n : k, tb ? k : n, 2);
      const Eigen::MatrixXd C0 = random_matrix(m, n, 3);
      const double alpha = 0.75, beta = -0.5;
      const Eigen::MatrixXd C = same_on_one_and_two_threads(
          [&] {
            Eigen::MatrixXd out = C0;
            const int lda = static_cast<int>(A.rows()), ldb = static_cast<int>(B.rows());
            dgemm_(transa, transb, &m, &n, &k, &alpha, A.data(), &lda, B.data(), &ldb, &beta, out.data(), &m);
            return out;
          },
          1);
      const Eigen::MatrixXd opA = ta ? Eigen::MatrixXd(A.transpose()) : A;
      const Eigen::MatrixXd opB = tb ? Eigen::MatrixXd(B.transpose()) : B;
      const Eigen::MatrixXd expected = alpha * opA * opB + beta * C0;
      EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-12 * k) << transa << transb;
    }
}

TEST(TiledBlas, SyrkFillsTheLowerTriangleAndLeavesTheUpperAlone) {
  const int n = 1100, k = 200;
  for (const char* trans : {"N", "T"}) {
    const bool t = *trans == 'T';
    const Eigen::MatrixXd A = random_matrix(t ? k : n, t ? n : k, 4);
    const Eigen::MatrixXd C0 = random_matrix(n, n, 5);
    const double alpha = -1, beta = 1;
    const Eigen::MatrixXd C = same_on_one_and_two_threads(
        [&] {
          Eigen::MatrixXd out = C0;
          const int lda = static_cast<int>(A.rows());
          dsyrk_("L", trans, &n, &k, &alpha, A.data(), &lda, &beta, out.data(), &n);
          return out;
        },
        1);
    const Eigen::MatrixXd opA = t ? Eigen::MatrixXd(A.transpose()) : A;
    const Eigen::MatrixXd expected = alpha * opA * opA.transpose() + beta * C0;
    for (int c = 0; c < n; ++c)
      for (int r = 0; r < n; ++r) {
        if (r >= c) ASSERT_NEAR(C(r, c), expected(r, c), 1e-12 * k) << trans << " at " << r << "," << c;
        else ASSERT_EQ(C(r, c), C0(r, c)) << "upper triangle written at " << r << "," << c;
      }
  }
}

// dtrsm_ with the lower-triangular L (non-unit diagonal) on a copy of B, on 1
// and on 2 threads (one tiled call each): the solution X.
Eigen::MatrixXd triangular_solve(const char* side, const char* transa, const Eigen::MatrixXd& L, double alpha,
                                 const Eigen::MatrixXd& B) {
  const int rows = static_cast<int>(B.rows()), columns = static_cast<int>(B.cols()), n = static_cast<int>(L.rows());
  return same_on_one_and_two_threads(
      [&] {
        Eigen::MatrixXd out = B;
        dtrsm_(side, "L", transa, "N", &rows, &columns, &alpha, L.data(), &n, out.data(), &rows);
        return out;
      },
      1);
}

TEST(TiledBlas, TrsmSolvesOnTheRightAndOnTheLeft) {
  const int n = 300;
  const Eigen::MatrixXd L = positive_definite(n, 6).llt().matrixL();
  const double alpha = 2;
  // X Lᵀ = alpha B, B tall (CHOLMOD's call): the rows are tiled.
  const Eigen::MatrixXd B = random_matrix(1300, n, 7);
  const Eigen::MatrixXd X = triangular_solve("R", "T", L, alpha, B);
  EXPECT_LT((X * L.transpose() - alpha * B).cwiseAbs().maxCoeff(), 1e-10);
  // L X = alpha B, B wide: the columns are tiled.
  const Eigen::MatrixXd W = random_matrix(n, 1300, 8);
  const Eigen::MatrixXd Y = triangular_solve("L", "N", L, alpha, W);
  EXPECT_LT((L * Y - alpha * W).cwiseAbs().maxCoeff(), 1e-10);
}

// A well-conditioned lower-triangular matrix: a dominant diagonal.
Eigen::MatrixXd lower_triangular(int n, unsigned seed) {
  Eigen::MatrixXd L = random_matrix(n, n, seed).triangularView<Eigen::StrictlyLower>();
  L /= std::sqrt(static_cast<double>(n));
  L.diagonal().array() += 2;
  return L;
}

TEST(TiledBlas, SolvesWithFewRightHandSidesRunByRowTiles) {
  const int m = 1600, n = 4;  // a triangle of 1.3 M entries, four row tiles, the last one short
  const Eigen::MatrixXd L = lower_triangular(m, 11);
  const Eigen::MatrixXd B = random_matrix(m, n, 12);
  for (const char* transa : {"N", "T"})
    for (const double alpha : {1.0, 2.0}) {
      const Eigen::MatrixXd X = triangular_solve("L", transa, L, alpha, B);
      const Eigen::MatrixXd opL = *transa == 'N' ? L : Eigen::MatrixXd(L.transpose());
      EXPECT_LT((opL * X - alpha * B).cwiseAbs().maxCoeff(), 1e-12) << transa << " alpha " << alpha;
    }
}

TEST(TiledBlas, AProductWithFewColumnsRunsByRowTiles) {
  const int m = 1300, n = 4, k = 1000;  // 10 MFlop, but 1.3 M entries of A to read
  const Eigen::MatrixXd A = random_matrix(m, k, 13), B = random_matrix(k, n, 14), C0 = random_matrix(m, n, 15);
  const double alpha = -1, beta = 1;
  const Eigen::MatrixXd C = same_on_one_and_two_threads(
      [&] {
        Eigen::MatrixXd out = C0;
        dgemm_("N", "N", &m, &n, &k, &alpha, A.data(), &m, B.data(), &k, &beta, out.data(), &m);
        return out;
      },
      1);
  EXPECT_LT((C - (alpha * A * B + beta * C0)).cwiseAbs().maxCoeff(), 1e-12 * k);
}

TEST(TiledBlas, PotrfFactorsByTiles) {
  const int n = 1300;  // three tiles, the last one short
  const Eigen::MatrixXd M = positive_definite(n, 9);
  const Eigen::MatrixXd F = same_on_one_and_two_threads(
      [&] {
        Eigen::MatrixXd out = M;
        int info = -1;
        dpotrf_("L", &n, out.data(), &n, &info);
        EXPECT_EQ(info, 0);
        return out;
      },
      1);
  const Eigen::MatrixXd L = F.triangularView<Eigen::Lower>();
  EXPECT_LT((L * L.transpose() - M).cwiseAbs().maxCoeff() / M.cwiseAbs().maxCoeff(), 1e-14);
}

TEST(TiledBlas, PotrfReportsTheFirstColumnThatIsNotPositiveDefinite) {
  const int n = 1300, bad = 700;  // in the second tile
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n);
  M(bad, bad) = -1;
  int info = 0;
  const std::int64_t start = tiled_blas_calls().tiled;
  dpotrf_("L", &n, M.data(), &n, &info);
  EXPECT_EQ(tiled_blas_calls().tiled - start, 1);
  EXPECT_EQ(info, bad + 1);  // LAPACK counts columns from 1
}

TEST(TiledBlas, SmallCallsGoToTheSystemBlasAsTheyCame) {
  const int n = 64;
  const Eigen::MatrixXd M = positive_definite(n, 10);
  Eigen::MatrixXd F = M;
  const TiledBlasCalls before = tiled_blas_calls();
  int info = -1;
  dpotrf_("L", &n, F.data(), &n, &info);
  const TiledBlasCalls after = tiled_blas_calls();
  EXPECT_EQ(info, 0);
  EXPECT_EQ(after.tiled, before.tiled);
  EXPECT_EQ(after.forwarded, before.forwarded + 1);
  const Eigen::MatrixXd L = F.triangularView<Eigen::Lower>();
  EXPECT_LT((L * L.transpose() - M).cwiseAbs().maxCoeff(), 1e-10);
}
