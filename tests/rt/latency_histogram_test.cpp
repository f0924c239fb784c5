// The latency histogram against a sorted-array oracle: quantile estimates within one bucket's
// width, exact count, min, max and mean, and no allocation when recording.
#include "sculpt/rt/latency_histogram.hpp"

#include "support/allocation_counter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace sculpt::rt {
namespace {

// Nearest-rank quantile of sorted samples: the ceil(q n)-th smallest.
std::int64_t oracle_quantile(const std::vector<std::int64_t>& sorted, double q) {
  const auto n = static_cast<double>(sorted.size());
  const auto rank = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(q * n)));
  return sorted[rank - 1];
}

void expect_quantiles_within_a_bucket(const LatencyHistogram& h, std::vector<std::int64_t> samples) {
  std::sort(samples.begin(), samples.end());
  for (double q : {0.001, 0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999}) {
    const std::int64_t truth = oracle_quantile(samples, q);
    const std::size_t b = h.bucket_of(truth);
    const std::int64_t width = h.bucket_upper(b) - h.bucket_lower(b);
    EXPECT_LE(std::abs(h.quantile(q) - truth), width) << "q=" << q << " truth=" << truth;
  }
  EXPECT_EQ(h.max(), samples.back());
  EXPECT_EQ(h.min(), samples.front());
  EXPECT_EQ(h.quantile(1.0), samples.back());
  EXPECT_EQ(h.quantile(0.0), samples.front());
}

TEST(LatencyHistogram, BucketsAreLogSpacedFrom100NanosecondsToOneSecond) {
  const LatencyHistogram h;
  EXPECT_EQ(h.bucket_of(0), 0u);
  EXPECT_EQ(h.bucket_of(99), 0u);
  EXPECT_EQ(h.bucket_of(100), 1u);
  EXPECT_EQ(h.bucket_lower(1), 100);
  EXPECT_EQ(h.bucket_of(-5), 0u);
  // 1 us starts the second decade, 1 ms the fifth, 1 s is overflow.
  EXPECT_EQ(h.bucket_lower(1 + LatencyHistogram::kBucketsPerDecade), 1'000);
  EXPECT_EQ(h.bucket_lower(1 + 4 * LatencyHistogram::kBucketsPerDecade), 1'000'000);
  EXPECT_EQ(h.bucket_of(999'999'999), LatencyHistogram::kBucketCount - 2);
  EXPECT_EQ(h.bucket_of(1'000'000'000), LatencyHistogram::kBucketCount - 1);
  EXPECT_EQ(h.bucket_of(std::numeric_limits<std::int64_t>::max()), LatencyHistogram::kBucketCount - 1);
  const double ratio = std::pow(10.0, 1.0 / LatencyHistogram::kBucketsPerDecade);
  for (std::size_t i = 1; i + 1 < LatencyHistogram::kBucketCount; ++i) {
    EXPECT_EQ(h.bucket_upper(i), h.bucket_lower(i + 1));
    const double r = static_cast<double>(h.bucket_upper(i)) / static_cast<double>(h.bucket_lower(i));
    // Integer edges: rounding moves the ratio by at most 1 ns over the lowest (100 ns) edges.
    EXPECT_NEAR(r, ratio, 1.2e-2) << "bucket " << i;
    // Every value lands in the bucket whose bounds hold it.
    for (std::int64_t v : {h.bucket_lower(i), h.bucket_upper(i) - 1}) EXPECT_EQ(h.bucket_of(v), i);
  }
}

TEST(LatencyHistogram, QuantilesMatchASortedArrayOracleWithinABucket) {
  std::mt19937_64 rng(2024);
  // Log-normal around 50 us, spanning 100 ns to tens of milliseconds, a few below and above.
  std::lognormal_distribution<double> d(std::log(50'000.0), 2.0);
  LatencyHistogram h;
  std::vector<std::int64_t> samples;
  for (int i = 0; i < 100'000; ++i) {
    const auto v = static_cast<std::int64_t>(d(rng));
    samples.push_back(v);
    h.add(v);
  }
  EXPECT_EQ(h.count(), samples.size());
  const long double sum = std::accumulate(samples.begin(), samples.end(), 0.0L);
  EXPECT_NEAR(h.mean(), static_cast<double>(sum / samples.size()), 1e-6);
  expect_quantiles_within_a_bucket(h, samples);
  const std::uint64_t in_buckets = [&] {
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < LatencyHistogram::kBucketCount; ++i) total += h.bucket_count(i);
    return total;
  }();
  EXPECT_EQ(in_buckets, h.count());
}

TEST(LatencyHistogram, FewAndClusteredSamples) {
  for (const std::vector<std::int64_t>& samples :
       {std::vector<std::int64_t>{42'000}, std::vector<std::int64_t>{10, 20, 30},
        std::vector<std::int64_t>{1'000'000, 1'000'001, 1'000'002, 5'000'000},
        std::vector<std::int64_t>{3, 2'000'000'000, 150'000}}) {
    LatencyHistogram h;
    for (std::int64_t v : samples) h.add(v);
    expect_quantiles_within_a_bucket(h, samples);
  }
  // A single value is reported exactly: the bucket middle is clamped to the exact min and max.
  LatencyHistogram one;
  one.add(123'456);
  EXPECT_EQ(one.median(), 123'456);
  EXPECT_EQ(one.p99(), 123'456);
}

TEST(LatencyHistogram, EmptyAndClear) {
  LatencyHistogram h;
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.median(), 0);
  EXPECT_EQ(h.max(), 0);
  EXPECT_EQ(h.mean(), 0.0);
  h.add(5'000);
  h.add(-20);  // counted as 0
  EXPECT_EQ(h.min(), 0);
  EXPECT_EQ(h.count(), 2u);
  h.clear();
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.max(), 0);
  EXPECT_EQ(h.quantile(0.5), 0);
  h.add(7'000);
  EXPECT_EQ(h.min(), 7'000);
  EXPECT_EQ(h.max(), 7'000);
}

TEST(LatencyHistogram, RecordingAndQueryingAllocateNothing) {
  LatencyHistogram h;
  std::int64_t sink = 0;
  test::AllocationCounter guard;
  for (std::int64_t v = 0; v < 2'000'000'000; v = v * 3 + 17) h.add(v);
  sink += h.median() + h.p99() + h.max();
  h.clear();
  EXPECT_EQ(guard.count(), 0u);
  EXPECT_GT(sink, 0);
}

}  // namespace
}  // namespace sculpt::rt
