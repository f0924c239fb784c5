// The statistics of `sculpt deform --repeat`: the cold first run apart, the median and the
// nearest-rank p99 over all runs, worked out by hand here.

#include <gtest/gtest.h>

#include <vector>

#include "repeat_timing.hpp"

namespace sculpt::tools {
namespace {

TEST(RepeatTiming, KeepsTheColdRunAndTakesMedianAndP99OverAllRuns) {
  // 1..100 shuffled, the first (cold) run the slowest: median 50.5, p99 the 99th smallest.
  std::vector<double> times;
  times.push_back(100.0);
  for (int k = 99; k >= 1; --k) times.push_back(static_cast<double>(k));
  const RepeatTimes t = summarise_repeats(times);
  EXPECT_EQ(t.cold_ms, 100.0);
  EXPECT_EQ(t.median_ms, 50.5);
  EXPECT_EQ(t.p99_ms, 99.0);
}

TEST(RepeatTiming, FewRunsGiveTheLargestAsP99AndTheMiddleAsMedian) {
  const RepeatTimes t = summarise_repeats({3.0, 1.0, 2.0});
  EXPECT_EQ(t.cold_ms, 3.0);
  EXPECT_EQ(t.median_ms, 2.0);
  EXPECT_EQ(t.p99_ms, 3.0);
  const RepeatTimes one = summarise_repeats({0.25});
  EXPECT_EQ(one.cold_ms, 0.25);
  EXPECT_EQ(one.median_ms, 0.25);
  EXPECT_EQ(one.p99_ms, 0.25);
}

}  // namespace
}  // namespace sculpt::tools
