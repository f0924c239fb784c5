#pragma once
// Durations of the loop (time used per tick, wake-up lateness) in fixed log-spaced buckets:
// a constant relative resolution from 100 ns to 1 s, fixed storage, so recording is cheap and
// never allocates.

#include <array>
#include <cstddef>
#include <cstdint>

namespace sculpt::rt {

/// A histogram of durations in nanoseconds. Buckets: [0, 100 ns), then kBucketsPerDecade per
/// decade from 100 ns to 1 s (each about 12 % wide), then [1 s, inf). add() is noexcept and
/// allocation-free; the exact minimum, maximum and mean are kept beside the buckets.
class LatencyHistogram {
 public:
  /// 100 ns: lower edge of the log buckets (a light tick takes well under 1 us).
  static constexpr std::int64_t kLowestNs = 100;
  static constexpr std::int64_t kHighestNs = 1'000'000'000;  ///< 1 s: upper edge of the log buckets
  static constexpr std::size_t kDecades = 7;
  static constexpr std::size_t kBucketsPerDecade = 20;
  /// Log buckets plus the underflow and overflow buckets.
  static constexpr std::size_t kBucketCount = kDecades * kBucketsPerDecade + 2;

  LatencyHistogram() noexcept;

  /// Records one duration; negative values (a clock read out of order) count as 0.
  void add(std::int64_t ns) noexcept;
  /// Forgets every sample.
  void clear() noexcept;

  std::uint64_t count() const noexcept { return count_; }
  /// Exact smallest sample (0 when empty).
  std::int64_t min() const noexcept { return count_ == 0 ? 0 : min_; }
  /// Exact largest sample (0 when empty).
  std::int64_t max() const noexcept { return max_; }
  /// Exact mean (0 when empty).
  double mean() const noexcept;

  /// Estimate of the q-quantile (nearest rank: the ceil(q n)-th smallest sample, q in [0, 1]):
  /// the middle of the bucket holding it, clamped to the exact min and max, so the error is at
  /// most one bucket's width (about 12 % of the value). 0 when empty.
  std::int64_t quantile(double q) const noexcept;
  std::int64_t median() const noexcept { return quantile(0.5); }
  std::int64_t p99() const noexcept { return quantile(0.99); }

  /// The bucket a duration falls in (a negative one: bucket 0).
  std::size_t bucket_of(std::int64_t ns) const noexcept;
  /// Lower edge of bucket `i` (inclusive).
  std::int64_t bucket_lower(std::size_t i) const noexcept { return edges_[i]; }
  /// Upper edge of bucket `i` (exclusive); the overflow bucket's is INT64_MAX.
  std::int64_t bucket_upper(std::size_t i) const noexcept { return edges_[i + 1]; }
  /// Samples in bucket `i`.
  std::uint64_t bucket_count(std::size_t i) const noexcept { return buckets_[i]; }

 private:
  std::array<std::int64_t, kBucketCount + 1> edges_{};  // bucket i is [edges_[i], edges_[i + 1])
  std::array<std::uint64_t, kBucketCount> buckets_{};
  std::uint64_t count_ = 0;
  std::int64_t min_ = 0;
  std::int64_t max_ = 0;
  long double sum_ = 0.0L;  // exact for any realistic number of nanosecond samples
};

}  // namespace sculpt::rt
