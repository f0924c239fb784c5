// A row's times: the median and the 99th percentile by nearest rank (the smallest value with at
// least that share of the samples at or below it), counted here by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "row.hpp"

namespace sculpt::tools::report {
namespace {

TEST(ReportRow, MedianAndP99AreNearestRanks) {
  std::vector<double> ns;
  for (int k = 1; k <= 200; ++k) ns.push_back(k * 1e3);  // 1 .. 200 us
  std::shuffle(ns.begin(), ns.end(), std::mt19937(7));
  Row r;
  set_times(r, ns);
  EXPECT_EQ(r.frames, 200u);
  EXPECT_DOUBLE_EQ(r.median_ms, 0.100);  // 100 of 200 at or below 100 us
  EXPECT_DOUBLE_EQ(r.p99_ms, 0.198);     // 198 of 200 at or below 198 us
}

TEST(ReportRow, OneSampleIsEveryRankAndNoneLeavesZeros) {
  Row one;
  set_times(one, {5e6});
  EXPECT_DOUBLE_EQ(one.median_ms, 5.0);
  EXPECT_DOUBLE_EQ(one.p99_ms, 5.0);
  Row none;
  set_times(none, {});
  EXPECT_EQ(none.frames, 0u);
  EXPECT_EQ(none.median_ms, 0.0);
}

}  // namespace
}  // namespace sculpt::tools::report
