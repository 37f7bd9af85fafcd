// The memory limit (memory_limit.hpp): its default, its setting and its refusals.
#include "animanifold/memory_limit.hpp"

#include "animanifold/errors.hpp"

#include <gtest/gtest.h>

#include <new>
#include <optional>
#include <string>

using namespace animanifold;

namespace {

// Sets a limit for one test and returns to the default after it, whatever happens.
struct ScopedLimit {
  explicit ScopedLimit(std::uint64_t bytes) { set_memory_limit(bytes); }
  ~ScopedLimit() { set_memory_limit(std::nullopt); }
};

std::string refusal(const MemoryEstimate& estimate) {  // the message, or "" when accepted
  try {
    check_memory(estimate);
  } catch (const MemoryLimitError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MemoryLimit, DefaultsToHalfTheAvailableMemoryAndCanBeSet) {
  EXPECT_FALSE(memory_limit_setting().has_value());
  EXPECT_GT(available_memory(), 0u);
  {
    const ScopedLimit limit(12345);
    EXPECT_EQ(memory_limit(), 12345u);
    EXPECT_EQ(memory_limit_setting(), std::optional<std::uint64_t>(12345));
  }
  EXPECT_FALSE(memory_limit_setting().has_value());
  // Available memory moves between two reads: a quarter of it either way is plenty.
  const double half = static_cast<double>(available_memory()) / 2;
  EXPECT_NEAR(static_cast<double>(memory_limit()), half, half / 4);
  EXPECT_THROW(set_memory_limit(0), InputError);
}

TEST(MemoryLimit, AnEstimateBeyondTheLimitIsRefusedNamingTheWorkTheEstimateAndTheLimit) {
  const ScopedLimit limit(1000);
  EXPECT_NO_THROW(check_memory("stitching a little", 1000));
  EXPECT_EQ(refusal({"stitching a lot", 2048.0 * 1024 * 1024}),
            "stitching a lot needs about 2,147,483,648 bytes (2 GiB), more than the memory limit of 1,000 bytes "
            "(set by animanifold.set_memory_limit)");
  // Estimates of hostile inputs overflow 64 bits; they are refused all the same.
  EXPECT_NE(refusal({"subdividing 40 times", 1e300}), "");
}

// Like running out of memory, a refusal passes through the translator of library failures.
TEST(MemoryLimit, ARefusalPassesThroughTheLibraryTranslatorAsRunningOutOfMemoryDoes) {
  const auto refuse = []() -> int { fail<MemoryLimitError>("stitching a lot needs more"); };
  EXPECT_THROW(translating_library_failures("CGAL", "x", refuse), MemoryLimitError);
  try {
    refuse();
  } catch (const std::bad_alloc& e) {
    EXPECT_STREQ(e.what(), "stitching a lot needs more");
  }
}
