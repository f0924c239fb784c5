// The queue every I/O thread hands data to the loop through: bounded, in order, nothing lost or
// duplicated across two threads (the TSan pass checks the memory ordering), and wait-free on
// both sides: a full queue refuses instead of blocking.
#include "sculpt/base/spsc_queue.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

namespace sculpt::base {
namespace {

TEST(SpscQueue, CapacityIsThePowerOfTwoAtOrAboveTheRequest) {
  EXPECT_EQ(SpscQueue<int>(0).capacity(), 2u);
  EXPECT_EQ(SpscQueue<int>(3).capacity(), 4u);
  EXPECT_EQ(SpscQueue<int>(64).capacity(), 64u);
  EXPECT_EQ(SpscQueue<int>(65).capacity(), 128u);
}

TEST(SpscQueue, FullRefusesEmptyRefusesAndOrderIsKeptAcrossTheWrap) {
  SpscQueue<int> q(4);
  int out = -1;
  EXPECT_FALSE(q.pop(out));
  for (int round = 0; round < 3; ++round) {  // the indices wrap around the slots
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.push(10 * round + i));
    EXPECT_FALSE(q.push(99)) << "a full queue must refuse";
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(q.pop(out));
      EXPECT_EQ(out, 10 * round + i);
    }
    EXPECT_FALSE(q.pop(out));
  }
}

TEST(SpscQueue, TwoThreadsPassTwoHundredThousandValuesInOrderWithNoneLostOrRepeated) {
  struct Item {
    std::uint64_t value, check;  // two words, so a torn copy would show
  };
  SpscQueue<Item> q(256);
  constexpr std::uint64_t kCount = 200'000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount;) {
      if (q.push({i, ~i})) ++i;
    }
  });
  std::uint64_t expected = 0, torn = 0, out_of_order = 0;
  Item item{};
  while (expected < kCount) {
    if (!q.pop(item)) continue;
    torn += item.check != ~item.value;
    out_of_order += item.value != expected;
    expected = item.value + 1;
  }
  producer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_FALSE(q.pop(item));
}

}  // namespace
}  // namespace sculpt::base
