// A Boolean operation run in a child process (isolated_boolean.hpp), with stand-ins for
// CGAL: what it returns or throws comes back, and one that never ends is stopped by the
// time limit or the interrupter.
#include "isolated_boolean.hpp"

#include "animanifold/errors.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

using namespace animanifold;
using holes::BooleanOutcome;
using holes::isolated_boolean;

namespace {

BooleanOutcome triangle() {
  BooleanOutcome outcome;
  outcome.solid.vertices.resize(3, 3);
  outcome.solid.vertices << 0, 0, 0, 1, 0, 0.5, 0, 1, 1e-300;
  outcome.solid.faces.resize(1, 3);
  outcome.solid.faces << 0, 1, 2;
  outcome.changed = false;
  return outcome;
}

// A Boolean that never finishes, as CGAL's corefinement on some inputs with its assertions on.
BooleanOutcome never_ends() {
  for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
}

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(IsolatedBoolean, TheChildsSolidComesBackBitForBit) {
  const BooleanOutcome back = isolated_boolean("testing", triangle, 10, {});
  EXPECT_EQ(back.solid.vertices, triangle().solid.vertices);
  EXPECT_EQ(back.solid.faces, triangle().solid.faces);
  EXPECT_FALSE(back.changed);
  const BooleanOutcome empty = isolated_boolean("testing", [] { return BooleanOutcome{}; }, 10, {});
  EXPECT_EQ(empty.solid.vertices.rows(), 0);
  EXPECT_TRUE(empty.changed);
}

TEST(IsolatedBoolean, OurErrorsInTheChildComeBackAsThemselves) {
  const auto refuses_input = []() -> BooleanOutcome { fail<InputError>("the frame is open (3 boundary edges)"); };
  const auto refuses_boolean = []() -> BooleanOutcome { fail<BooleanError>("CGAL refused the hole space"); };
  EXPECT_THROW(isolated_boolean("testing", refuses_input, 10, {}), InputError);
  EXPECT_EQ(message_of([&] { isolated_boolean("testing", refuses_input, 10, {}); }),
            "the frame is open (3 boundary edges)");
  EXPECT_THROW(isolated_boolean("testing", refuses_boolean, 10, {}), BooleanError);
  EXPECT_EQ(message_of([&] { isolated_boolean("testing", refuses_boolean, 10, {}); }), "CGAL refused the hole space");
}

TEST(IsolatedBoolean, ABooleanThatNeverEndsIsKilledAtItsTimeLimit) {
  EXPECT_THROW(isolated_boolean("subtracting a solid from the frame", never_ends, 1, {}), TimeLimitError);
  const std::string message =
      message_of([] { isolated_boolean("subtracting a solid from the frame", never_ends, 1, {}); });
  EXPECT_NE(message.find("subtracting a solid from the frame"), std::string::npos) << message;
  EXPECT_NE(message.find("did not finish within 1 s"), std::string::npos) << message;
}

TEST(IsolatedBoolean, TheInterrupterStopsABooleanWhileItRuns) {
  int polls = 0;
  Interrupter interrupter;
  interrupter.interrupted = [&] { return ++polls >= 3; };  // the first polls let the child start
  EXPECT_THROW(isolated_boolean("testing", never_ends, 0, interrupter), Cancelled);
  EXPECT_EQ(polls, 3);
  // Asked to stop before it starts: the child is never made.
  Interrupter stop;
  stop.interrupted = [] { return true; };
  EXPECT_THROW(isolated_boolean("testing", triangle, 0, stop), Cancelled);
}

TEST(IsolatedBoolean, TheTimeLimitGrowsWithTheOperandsAndStaysAboveAMinute) {
  EXPECT_GE(holes::boolean_time_limit(0), 60.0);
  EXPECT_GT(holes::boolean_time_limit(1'000'000), holes::boolean_time_limit(1000));
}
