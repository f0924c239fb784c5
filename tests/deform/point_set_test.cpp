// PointSet against std::set: whatever the order and repetition of the insertions, drain() lists
// each index once, ascending, and leaves the set empty for the next frame.
#include "sculpt/deform/point_set.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

namespace sculpt::deform {
namespace {

TEST(PointSet, DrainsEveryIndexOnceAscendingAndEmpties) {
  // 300,000 indices: more than one summary word (4,096 indices each) and a last word in part.
  constexpr std::uint32_t kSize = 300000;
  PointSet set(kSize);
  std::mt19937 rng(7);
  std::vector<std::uint32_t> out;
  out.reserve(kSize);
  for (const std::uint32_t count : {0u, 1u, 50u, 5000u, 200000u}) {
    std::set<std::uint32_t> want;
    std::uniform_int_distribution<std::uint32_t> any(0, kSize - 1);
    for (std::uint32_t k = 0; k < count; ++k) {
      // Clusters of near indices, repeated, as overlapping balls give them; and both ends.
      const std::uint32_t i = k % 3 == 0 ? any(rng) : (any(rng) % 64) + (kSize / 2);
      set.insert(i);
      want.insert(i);
    }
    if (count > 0) {
      set.insert(0);
      set.insert(kSize - 1);
      want.insert(0);
      want.insert(kSize - 1);
    }
    out.clear();
    EXPECT_TRUE(set.drain(out));
    EXPECT_EQ(out, std::vector<std::uint32_t>(want.begin(), want.end())) << count << " insertions";
    out.clear();
    EXPECT_TRUE(set.drain(out));
    EXPECT_TRUE(out.empty()) << "the set is empty after a drain";
  }
}

TEST(PointSet, ADrainBeyondTheCapacityReportsItAndStillEmpties) {
  PointSet set(1000);
  for (std::uint32_t i = 0; i < 1000; i += 10) set.insert(i);
  std::vector<std::uint32_t> out;
  out.reserve(30);
  EXPECT_FALSE(set.drain(out));
  ASSERT_EQ(out.size(), 30u);
  EXPECT_EQ(out.front(), 0u);
  EXPECT_EQ(out.back(), 290u);
  out.clear();
  EXPECT_TRUE(set.drain(out));
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace sculpt::deform
