// Index and count checks shared by the core's entry points (validation.hpp).
#include "animanifold/validation.hpp"

#include "animanifold/errors.hpp"
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>

using namespace animanifold;

namespace {

std::string message_of(const std::function<void()>& call) { return fixtures::input_error_message(call); }

}  // namespace

TEST(Validation, IndicesInRangePass) {
  SimplexMatrix F(2, 3);
  F << 0, 1, 2, 2, 1, 3;
  EXPECT_NO_THROW(check_indices(F, 4, "face"));
  EXPECT_NO_THROW(check_indices(SimplexMatrix(0, 3), 0, "face"));
}

TEST(Validation, TheFirstBadIndexIsNamedWithItsRowAndValue) {
  SimplexMatrix F(3, 3);
  F << 0, 1, 2, 2, 100000000, 3, 0, -1000000, 1;
  EXPECT_EQ(message_of([&] { check_indices(F, 4, "face"); }), "face 1 refers to vertex 100000000, outside 0..3");
  F(1, 1) = 3;
  EXPECT_EQ(message_of([&] { check_indices(F, 4, "simplex"); }), "simplex 2 refers to vertex -1000000, outside 0..3");
  EXPECT_EQ(message_of([&] { check_indices(F, 0, "face"); }), "face 0 refers to vertex 0, but there are no vertices");
}

TEST(Validation, CountsBeyondTheLargestIndexAreRefused) {
  EXPECT_EQ(checked_index_count(2147483647, "points"), 2147483647);
  EXPECT_EQ(message_of([] { checked_index_count(std::int64_t{1} << 31, "the manifold's points"); }),
            "the manifold's points: 2147483648 is more than a 32-bit index can address (at most 2147483647)");
  EXPECT_THROW(checked_index_count(-1, "points"), InputError);
}
