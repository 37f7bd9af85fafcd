// The OpenMP team cap (openmp_team_cap.hpp): a team that asks for more
// threads than thread_count() gets thread_count(), CHOLMOD's own loops
// included, and a factor made under the cap still solves its system.
#include "openmp_team_cap.hpp"

#include "animanifold/threads.hpp"
#include "sparse_cholesky.hpp"

#include <Eigen/Sparse>
#include <gtest/gtest.h>
#include <omp.h>

#include <vector>

using namespace animanifold;

namespace {

// The team size of a region that asks for `requested` threads.
int team_size_asking(int requested) {
  int size = 0;
#pragma omp parallel num_threads(requested)
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  return size;
}

// The 5-point Laplacian of a side x side grid plus the identity (positive
// definite), lower triangle: its nested-dissection separators give CHOLMOD
// supernodes of about `side` columns, tall enough for its OpenMP loops.
Eigen::SparseMatrix<double, Eigen::ColMajor, int> grid_matrix_lower(int side) {
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> entries;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      entries.emplace_back(i, i, 5.0);
      if (x + 1 < side) entries.emplace_back(i + 1, i, -1.0);
      if (y + 1 < side) entries.emplace_back(i + side, i, -1.0);
    }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> lower(n, n);
  lower.setFromTriplets(entries.begin(), entries.end());
  lower.makeCompressed();
  return lower;
}

class OpenmpTeamCap : public ::testing::Test {
 protected:
  void TearDown() override { set_thread_count(before_); }
  int before_ = thread_count();
};

}  // namespace

TEST_F(OpenmpTeamCap, ATeamAskingForMoreThreadsGetsTheThreadCount) {
  for (int count : {1, 2}) {
    set_thread_count(count);
    const std::int64_t start = openmp_teams_capped();
    EXPECT_EQ(team_size_asking(4), count);
    EXPECT_EQ(openmp_teams_capped() - start, 1);
  }
}

TEST_F(OpenmpTeamCap, ATeamOfTheThreadsDefaultSizeIsHeldToo) {
  set_thread_count(2);
  const int setting = omp_get_max_threads();
  omp_set_num_threads(4);  // as a thread the core never set could have it
  const std::int64_t start = openmp_teams_capped();
  int size = 0;
#pragma omp parallel
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  omp_set_num_threads(setting);
  EXPECT_EQ(size, 2);
  EXPECT_EQ(openmp_teams_capped() - start, 1);
}

TEST_F(OpenmpTeamCap, ATeamWithinTheThreadCountIsLeftAsAsked) {
  set_thread_count(4);
  const std::int64_t start = openmp_teams_capped();
  EXPECT_EQ(team_size_asking(3), 3);
  EXPECT_EQ(team_size_asking(1), 1);
  EXPECT_EQ(openmp_teams_capped() - start, 0);
}

TEST_F(OpenmpTeamCap, CholmodsOwnLoopsAreHeldToTheThreadCount) {
  set_thread_count(2);
  const auto lower = grid_matrix_lower(160);
  SparseCholesky cholesky;
  const std::int64_t start = openmp_teams_capped();
  ASSERT_TRUE(cholesky.factor(lower));
  EXPECT_GT(openmp_teams_capped() - start, 0) << "CHOLMOD's OpenMP loops did not reach the cap";
  EXPECT_EQ(cholesky.openmp_teams_capped(), openmp_teams_capped() - start);

  const Eigen::SparseMatrix<double> full =
      Eigen::SparseMatrix<double>(lower.selfadjointView<Eigen::Lower>());
  const Eigen::MatrixXd expected = Eigen::MatrixXd::Random(lower.rows(), 3);
  const Eigen::MatrixXd x = cholesky.solve(full * expected);
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-12);
}
