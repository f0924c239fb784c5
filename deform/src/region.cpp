#include "sculpt/deform/region.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::deform {
namespace {

// Sorts `values` ascending by least-significant-digit radix sort through `buffer` (whose
// capacity must hold them; never grown, so nothing is allocated): as few passes of at most 11
// bits as the largest value needs, the bits shared evenly between them (two passes of 9 bits
// below 2^18 points: a quarter of the buckets to clear and sum that 11 bits would have, and
// their counts stay in the first-level cache). std::sort on a region's few thousand scattered
// indices mispredicted a branch per comparison and was a third of building it.
void radix_sort(std::vector<std::uint32_t>& values, std::vector<std::uint32_t>& buffer) noexcept {
  constexpr int kMaxBits = 11;
  if (values.size() < 2) return;
  const std::uint32_t largest = *std::max_element(values.begin(), values.end());
  const int bits = std::bit_width(largest);
  if (bits == 0) return;
  const int passes = (bits + kMaxBits - 1) / kMaxBits;
  const int digit = (bits + passes - 1) / passes;
  const std::uint32_t buckets = 1u << digit, mask = buckets - 1;
  buffer.resize(values.size());
  // Four histograms, value k counted in histogram k % 4: values in a row that share a digit
  // (most of them in the high digit's pass: the region comes in clusters of near indices) would
  // otherwise each wait for the count the one before stored.
  constexpr std::size_t kHistograms = 4;
  std::array<std::array<std::uint32_t, 1u << kMaxBits>, kHistograms> histogram;
  std::array<std::uint32_t, 1u << kMaxBits> count;
  const std::size_t whole = values.size() - values.size() % kHistograms;
  for (int shift = 0; shift < bits; shift += digit) {
    for (auto& h : histogram) std::fill_n(h.begin(), buckets, 0u);
    for (std::size_t k = 0; k < whole; k += kHistograms) {
      for (std::size_t h = 0; h < kHistograms; ++h) ++histogram[h][(values[k + h] >> shift) & mask];
    }
    for (std::size_t k = whole; k < values.size(); ++k) ++histogram[0][(values[k] >> shift) & mask];
    std::uint32_t start = 0;
    for (std::uint32_t b = 0; b < buckets; ++b) {
      count[b] = start;
      for (const auto& h : histogram) start += h[b];
    }
    for (std::uint32_t v : values) buffer[count[(v >> shift) & mask]++] = v;
    values.swap(buffer);
  }
}

// Whether no point can lie within `radius` of two of the contacts: every pair of centres is
// more than twice the radius apart, with a margin far above the rounding of the distances.
bool balls_apart(std::span<const Vec3> contacts, double radius) noexcept {
  const double apart = 2.0 * radius * (1.0 + 1e-9);
  for (std::size_t a = 0; a < contacts.size(); ++a) {
    for (std::size_t b = a + 1; b < contacts.size(); ++b) {
      if (!(squared_norm(contacts[a] - contacts[b]) > apart * apart)) return false;
    }
  }
  return true;
}

}  // namespace

Region::Region(const RegionSettings& settings, const PointModel& model, const PointIndex& index, double bc_radius)
    : settings_(settings),
      border_width_(settings.border_width > 0.0 ? settings.border_width : bc_radius),
      min_radius_(1.01 * (bc_radius + border_width_)) {
  using Kind = RegionSettings::Kind;
  if (!(settings_.border_weight >= 0.0) || !std::isfinite(settings_.border_weight)) {
    throw std::invalid_argument("region: border weight must be >= 0");
  }
  if (settings_.kind == Kind::kRadius) {
    // The contact's own neighbourhood must lie wholly inside the region and clear of the band,
    // or the frame would pin the very points it asks to move.
    if (!(settings_.radius > bc_radius + border_width_)) {
      throw std::invalid_argument("region: radius " + base::number_text(settings_.radius) +
                                  " must exceed the bc radius plus the border width (" +
                                  base::number_text(bc_radius + border_width_) + ")");
    }
  }
  const std::size_t n = model.size();
  points_.reserve(n);
  border_.reserve(n);
  scratch_.reserve(n);
  member_.assign(n, 0);
  if (settings_.kind == Kind::kIndices) {
    points_ = settings_.indices;
    std::sort(points_.begin(), points_.end());
    points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
    if (points_.empty()) throw std::invalid_argument("region: the index set is empty");
    if (points_.back() >= n) {
      throw std::invalid_argument("region: index " + std::to_string(points_.back()) + " is outside the model's " +
                                  std::to_string(n) + " points");
    }
    for (std::uint32_t i : points_) member_[i] = 1;
    // Band: region points with a point outside the region within the border width.
    for (std::uint32_t i : points_) {
      index.within_radius(model, model.position(i), border_width_, scratch_);
      if (std::any_of(scratch_.begin(), scratch_.end(), [&](std::uint32_t j) { return !member_[j]; })) {
        border_.push_back(i);
      }
    }
    for (std::uint32_t i : points_) member_[i] = 0;
  }
}

void Region::build(const PointModel& model, const PointIndex& index, double drift, std::span<const Vec3> contacts) {
  if (settings_.kind != RegionSettings::Kind::kRadius) return;  // fixed for the others
  points_.clear();
  border_.clear();
  const double inner = settings_.radius - border_width_;
  const double inner_squared = inner * inner;
  if (balls_apart(contacts, settings_.radius)) {
    // Fingers apart (the common case): no point is found twice, and a point can only be deep
    // in the ball that found it, so neither the per-point flags (two scattered accesses a
    // point) nor a test against every contact is needed. The band, sorted on its own, is the
    // same ascending list the general case builds.
    for (const Vec3& c : contacts) {
      index.within_radius(model, c, settings_.radius, scratch_, drift, /*ascending=*/false);
      for (std::uint32_t i : scratch_) {
        points_.push_back(i);
        if (!(squared_norm(model.position(i) - c) <= inner_squared)) border_.push_back(i);
      }
    }
    radix_sort(points_, scratch_);
    radix_sort(border_, scratch_);
    return;
  }
  for (const Vec3& c : contacts) {
    index.within_radius(model, c, settings_.radius, scratch_, drift, /*ascending=*/false);
    for (std::uint32_t i : scratch_) {
      if (!member_[i]) {
        member_[i] = 1;
        points_.push_back(i);
      }
    }
  }
  // points_ and scratch_ both hold the whole model (reserved at construction), and the swaps
  // inside the sort only exchange the two.
  radix_sort(points_, scratch_);
  // A point is in the band when it is not deeper than the border width inside any ball.
  for (std::uint32_t i : points_) {
    member_[i] = 0;
    const Vec3 q = model.position(i);
    const bool deep = std::any_of(contacts.begin(), contacts.end(),
                                  [&](const Vec3& c) { return squared_norm(q - c) <= inner_squared; });
    if (!deep) border_.push_back(i);
  }
}

}  // namespace sculpt::deform
