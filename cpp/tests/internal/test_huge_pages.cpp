// Asking for transparent huge pages (huge_pages.hpp): advice only, so a
// buffer keeps what it holds and any pointer and size is accepted. Whether
// the kernel grants huge pages depends on its THP mode and free memory, so no
// test asserts it; bench/bench_stitch_slice.py measures what it buys.
#include "huge_pages.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <algorithm>
#include <numeric>
#include <vector>

using animanifold::advise_huge_pages;

TEST(HugePages, AdviceKeepsTheBuffersContents) {
  std::vector<std::int64_t> buffer(3 << 20);  // 24 MiB, not 2 MiB aligned
  std::iota(buffer.begin(), buffer.end(), std::int64_t{-5});
  advise_huge_pages(buffer.data(), buffer.size() * sizeof(std::int64_t));
  for (size_t i = 0; i < buffer.size(); ++i) ASSERT_EQ(buffer[i], static_cast<std::int64_t>(i) - 5) << i;
  buffer.resize(buffer.size() * 2, 7);  // still usable: grows, writes, frees
  EXPECT_EQ(buffer.back(), 7);
}

TEST(HugePages, SmallEmptyAndOddBuffersAreLeftAlone) {
  advise_huge_pages(nullptr, 0);
  advise_huge_pages(nullptr, std::size_t{1} << 30);
  std::vector<char> small(4096, 'a');
  advise_huge_pages(small.data() + 1, small.size() - 1);
  EXPECT_EQ(std::count(small.begin(), small.end(), 'a'), 4096);
}
