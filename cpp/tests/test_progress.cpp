// The interrupter of long calls (progress.hpp), and that each long call
// stops at the step where its caller cancels.
#include "animanifold/errors.hpp"
#include "animanifold/laplacian.hpp"
#include "animanifold/progress.hpp"
#include "animanifold/stitch.hpp"
#include "animanifold/subdivide.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace animanifold;
using namespace animanifold::fixtures;

namespace {

// Records every step and cancels at the `cancel_at`-th (1-based; 0 never).
struct Recorder {
  std::vector<std::string> steps;
  std::vector<double> fractions;
  int cancel_at = 0;

  Interrupter interrupter() {
    return {[this](const std::string& step, double fraction) {
              steps.push_back(step);
              fractions.push_back(fraction);
              return static_cast<int>(steps.size()) != cancel_at;
            },
            {}};
  }
};

void expect_monotone_in_unit_interval(const std::vector<double>& fractions) {
  ASSERT_FALSE(fractions.empty());
  for (size_t i = 0; i < fractions.size(); ++i) {
    EXPECT_GE(fractions[i], 0.0);
    EXPECT_LE(fractions[i], 1.0);
    if (i > 0) EXPECT_GE(fractions[i], fractions[i - 1]) << "step " << i;
  }
}

}  // namespace

TEST(Interrupter, AnEmptyOneNeverStops) { EXPECT_NO_THROW(Interrupter{}.step("a", 0.5)); }

TEST(Interrupter, FalseFromProgressOrTrueFromInterruptedCancels) {
  int polls = 0;
  const Interrupter stop_on_second_poll{{}, [&] { return ++polls == 2; }};
  EXPECT_NO_THROW(stop_on_second_poll.step("a", 0));
  EXPECT_THROW(stop_on_second_poll.poll(), Cancelled);
  const Interrupter refuse{[](const std::string&, double) { return false; }, {}};
  EXPECT_THROW(refuse.step("a", 0), Cancelled);
}

TEST(Interrupter, FractionsAreClampedToTheUnitInterval) {
  Recorder r;
  const Interrupter i = r.interrupter();
  i.step("a", -0.5);
  i.step("b", 2.0);
  EXPECT_EQ(r.fractions, (std::vector<double>{0.0, 1.0}));
}

TEST(Interrupter, StitchReportsEachKeyframeGapAndStopsWhereCancelled) {
  const StitchInput input = octahedron_animation();
  Recorder all;
  stitch(input, all.interrupter());
  expect_monotone_in_unit_interval(all.fractions);
  EXPECT_EQ(all.steps.front(), "checks");
  EXPECT_EQ(all.steps.back(), "attributes");
  Recorder cancelling;
  cancelling.cancel_at = 2;
  EXPECT_THROW(stitch(input, cancelling.interrupter()), Cancelled);
  EXPECT_EQ(cancelling.steps.size(), 2u);
}

TEST(Interrupter, SubdivisionReportsEachLevelAndStopsWhereCancelled) {
  const Complex manifold = stitch(octahedron_animation());
  ManifoldSubdivisionOptions options;
  options.levels = 2;
  Recorder all;
  subdivide_manifold(manifold, options, all.interrupter());
  expect_monotone_in_unit_interval(all.fractions);
  EXPECT_EQ(all.steps, (std::vector<std::string>{"checks", "refining", "averaging", "refining", "averaging", "octahedra"}));
  Recorder cancelling;
  cancelling.cancel_at = 4;
  EXPECT_THROW(subdivide_manifold(manifold, options, cancelling.interrupter()), Cancelled);
  EXPECT_EQ(cancelling.steps.size(), 4u);
}

TEST(Interrupter, DeformerReportsEachIncrementAndRestoreRoundAndStopsWhereCancelled) {
  const Complex m = stitch(octahedron_animation());
  IndexVector anchors(6), handles(6);
  for (int i = 0; i < 6; ++i) anchors(i) = i, handles(i) = 12 + i;
  Deformer d(m.V, m.S, anchors, handles);
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(5, 5);
  T(2, 4) = 0.5;
  Recorder increments;
  d.deform(T, 3, increments.interrupter());
  EXPECT_EQ(increments.steps, (std::vector<std::string>{"deforming", "deforming", "deforming"}));
  expect_monotone_in_unit_interval(increments.fractions);
  Recorder rounds;
  const RestoreStatus status = d.restore(50, 1e-12, rounds.interrupter());
  EXPECT_EQ(rounds.steps, std::vector<std::string>(static_cast<size_t>(status.iterations), "restoring"));
  expect_monotone_in_unit_interval(rounds.fractions);
  Recorder cancelling;
  cancelling.cancel_at = 2;
  EXPECT_THROW(d.deform(T, 3, cancelling.interrupter()), Cancelled);
  EXPECT_EQ(cancelling.steps.size(), 2u);
  Recorder cancelling_restore;
  cancelling_restore.cancel_at = 1;
  EXPECT_THROW(d.restore(50, 1e-12, cancelling_restore.interrupter()), Cancelled);
  EXPECT_EQ(cancelling_restore.steps.size(), 1u);
}
