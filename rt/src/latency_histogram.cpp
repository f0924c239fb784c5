#include "sculpt/rt/latency_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sculpt::rt {

LatencyHistogram::LatencyHistogram() noexcept {
  // Integer edges, computed once, so bucket_of() and the reported bounds agree exactly.
  edges_[0] = 0;
  for (std::size_t i = 0; i <= kDecades * kBucketsPerDecade; ++i) {
    const double exponent = static_cast<double>(i) / static_cast<double>(kBucketsPerDecade);
    edges_[i + 1] = std::llround(static_cast<double>(kLowestNs) * std::pow(10.0, exponent));
  }
  edges_[kBucketCount] = std::numeric_limits<std::int64_t>::max();
}

void LatencyHistogram::add(std::int64_t ns) noexcept {
  ns = std::max<std::int64_t>(ns, 0);
  ++buckets_[bucket_of(ns)];
  if (count_ == 0 || ns < min_) min_ = ns;
  max_ = std::max(max_, ns);
  sum_ += static_cast<long double>(ns);
  ++count_;
}

void LatencyHistogram::clear() noexcept {
  buckets_.fill(0);
  count_ = 0;
  min_ = 0;
  max_ = 0;
  sum_ = 0.0L;
}

double LatencyHistogram::mean() const noexcept {
  return count_ == 0 ? 0.0 : static_cast<double>(sum_ / static_cast<long double>(count_));
}

std::size_t LatencyHistogram::bucket_of(std::int64_t ns) const noexcept {
  // The last edge <= ns (negative counts as 0, like add()); the final edge, INT64_MAX, is left
  // out of the search so that INT64_MAX itself lands in the overflow bucket too.
  const auto it = std::upper_bound(edges_.begin(), edges_.end() - 1, std::max<std::int64_t>(ns, 0));
  return static_cast<std::size_t>(it - edges_.begin()) - 1;
}

std::int64_t LatencyHistogram::quantile(double q) const noexcept {
  if (count_ == 0) return 0;
  if (!(q > 0.0)) return min_;  // also NaN
  if (q >= 1.0) return max_;
  const double n = static_cast<double>(count_);
  const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * n)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBucketCount; ++i) {
    seen += buckets_[i];
    if (seen >= rank) {
      // The overflow bucket has no middle: the exact max is the best estimate there.
      const std::int64_t middle = i + 1 == kBucketCount ? max_ : edges_[i] + (edges_[i + 1] - edges_[i]) / 2;
      return std::clamp(middle, min_, max_);
    }
  }
  return max_;
}

}  // namespace sculpt::rt
