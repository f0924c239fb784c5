#include "sculpt/deform/region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::deform {
namespace {

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

double region_border_width(const RegionSettings& settings, double bc_radius) {
  return settings.border_width > 0.0 ? settings.border_width : bc_radius;
}

double smallest_region_radius(const RegionSettings& settings, double bc_radius) {
  return bc_radius + region_border_width(settings, bc_radius);
}

Region::Region(const RegionSettings& settings, const PointModel& model, const PointIndex& index, double bc_radius)
    : settings_(settings),
      border_width_(region_border_width(settings, bc_radius)),
      min_radius_(1.01 * (bc_radius + border_width_)) {
  using Kind = RegionSettings::Kind;
  if (!(settings_.border_weight >= 0.0) || !std::isfinite(settings_.border_weight)) {
    throw std::invalid_argument("region: border weight must be >= 0");
  }
  if (settings_.kind == Kind::kRadius) {
    if (!(settings_.radius > smallest_region_radius(settings_, bc_radius))) {
      throw std::invalid_argument("region: radius " + base::number_text(settings_.radius) +
                                  " must exceed the bc radius plus the border width (" +
                                  base::number_text(smallest_region_radius(settings_, bc_radius)) + ")");
    }
  }
  measure_model(model);
  base_lo_ = box_lo_;
  base_hi_ = box_hi_;
  const std::size_t n = model.size();
  points_.reserve(n);
  border_.reserve(n);
  scratch_.reserve(n);
  if (settings_.kind == Kind::kRadius) {
    as_found_.reserve(n);
    found_ = PointSet(n);
    band_found_ = PointSet(n);
    balls_ = BallCache(n, BallCache::kRegionMargin, /*ascending=*/false);
  }
  if (settings_.kind == Kind::kIndices) {
    points_ = settings_.indices;
    std::sort(points_.begin(), points_.end());
    points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
    if (points_.empty()) throw std::invalid_argument("region: the index set is empty");
    if (points_.back() >= n) {
      throw std::invalid_argument("region: index " + std::to_string(points_.back()) + " is outside the model's " +
                                  std::to_string(n) + " points");
    }
    std::vector<std::uint8_t> member(n, 0);
    for (std::uint32_t i : points_) member[i] = 1;
    // Band: region points with a point outside the region within the border width.
    for (std::uint32_t i : points_) {
      index.within_radius(model, model.position(i), border_width_, scratch_);
      if (std::any_of(scratch_.begin(), scratch_.end(), [&](std::uint32_t j) { return !member[j]; })) {
        border_.push_back(i);
      }
    }
  }
}

void Region::measure_model(const PointModel& model) noexcept {
  const PointModel::Box box = model.bounding_box();
  box_lo_ = box.lo;
  box_hi_ = box.hi;
  moved_since_measure_ = 0.0;
}

double Region::farthest_point_bound(const Vec3& c) const noexcept {
  const double m = moved_since_measure_;
  const Vec3 reach{std::max(c.x - box_lo_.x, box_hi_.x - c.x) + m, std::max(c.y - box_lo_.y, box_hi_.y - c.y) + m,
                   std::max(c.z - box_lo_.z, box_hi_.z - c.z) + m};
  return norm(reach) * (1.0 + 1e-9);
}

void Region::set_radius(double radius) noexcept {
  // From a point in the box, the farthest is at most the box's diagonal away.
  const Vec3 diagonal = box_hi_ - box_lo_ + Vec3{1.0, 1.0, 1.0} * (2.0 * moved_since_measure_);
  const double holds_all = border_width_ + norm(diagonal) * (1.0 + 1e-9);
  if (radius > holds_all) radius = holds_all;
  settings_.radius = radius > min_radius_ ? radius : min_radius_;  // NaN: the smallest
}

void Region::build(const PointModel& model, const PointIndex& index, double drift, std::span<const Vec3> contacts) {
  if (settings_.kind != RegionSettings::Kind::kRadius) return;  // fixed for the others
  points_.clear();
  border_.clear();
  as_found_.clear();
  as_found_complete_ = true;
  scanned_ = false;
  // Every point within radius - band of one contact: all move, none is in the band.
  const double inner = settings_.radius - border_width_;
  moves_model_ =
      std::any_of(contacts.begin(), contacts.end(), [&](const Vec3& c) { return farthest_point_bound(c) <= inner; });
  if (moves_model_) return;
  const bool counted_past_share = collect(model, index, drift, contacts, inner * inner);
  balls_.end_frame();
  // The balls may hold every point after all (the box's corners lie beyond the model's points).
  const bool holds_model = points_.size() == model.size() && border_.empty();
  moves_model_ = holds_model || counted_past_share || past_cheaper_share(points_.size(), model.size());
  went_global_for_share_ = moves_model_ && !holds_model;
  if (moves_model_ && !holds_model) {  // the cheaper global frame: every point moves, no band
    points_.clear();
    border_.clear();
    as_found_.clear();
    as_found_complete_ = false;
  }
}

bool Region::collect(const PointModel& model, const PointIndex& index, double drift, std::span<const Vec3> contacts,
                     double inner_squared) {
  if (scan_pays(model.size(), contacts.size())) return scan(model, contacts, inner_squared);
  found_last_ = 0;
  // Overlapping balls repeat points: past the reserve the order is dropped, not grown.
  const auto keep_as_found = [&] {
    found_last_ += scratch_.size();
    if (as_found_.size() + scratch_.size() <= as_found_.capacity()) {
      as_found_.insert(as_found_.end(), scratch_.begin(), scratch_.end());
    } else {
      as_found_complete_ = false;
    }
  };
  if (balls_apart(contacts, settings_.radius)) {
    // Fingers apart (the common case): a point can only be deep in the ball that found it, so
    // the band is decided as each ball's points come, without a test against every contact.
    for (const Vec3& c : contacts) {
      balls_.within_radius(model, index, drift, c, settings_.radius, scratch_);
      keep_as_found();
      for (std::uint32_t i : scratch_) {
        found_.insert(i);
        if (!(squared_norm(model.position(i) - c) <= inner_squared)) band_found_.insert(i);
      }
    }
    found_.drain(points_);
    band_found_.drain(border_);
    return false;
  }
  // Overlapping balls: a point found twice is listed once, and it is in the band when it is
  // not deeper than the border width inside any ball.
  for (const Vec3& c : contacts) {
    balls_.within_radius(model, index, drift, c, settings_.radius, scratch_);
    keep_as_found();
    for (std::uint32_t i : scratch_) found_.insert(i);
  }
  found_.drain(points_);
  for (std::uint32_t i : points_) {
    const Vec3 q = model.position(i);
    const bool deep = std::any_of(contacts.begin(), contacts.end(),
                                  [&](const Vec3& c) { return squared_norm(q - c) <= inner_squared; });
    if (!deep) border_.push_back(i);
  }
  return false;
}

bool Region::scan_pays(std::size_t model_points, std::size_t contacts) const noexcept {
  // Measured on the bundled sphere and the 100k dragon (README, issue 10): a found point costs
  // the queries about as much as 14 to 18 point-contact tests of a scan.
  constexpr std::size_t kScanShare = 16;
  return contacts > 0 && found_last_ * kScanShare >= model_points * contacts;
}

bool Region::scan(const PointModel& model, std::span<const Vec3> contacts, double inner_squared) noexcept {
  as_found_complete_ = false;  // points() is the order found
  scanned_ = true;
  found_last_ = 0;
  const double radius_squared = settings_.radius * settings_.radius;
  const std::size_t n = model.size();
  // Each point's smallest squared distance to any contact, a chunk at a time, one contact at a
  // time so that the inner loop runs over contiguous coordinates (and vectorises); `visit` takes
  // each chunk's and returns false to stop.
  constexpr std::size_t kChunk = 256;
  alignas(64) double nearest[kChunk];
  const auto for_each_chunk = [&](auto&& visit) {
    for (std::size_t begin = 0; begin < n; begin += kChunk) {
      const std::size_t count = std::min(kChunk, n - begin);
      const float* x = model.x.data() + begin;
      const float* y = model.y.data() + begin;
      const float* z = model.z.data() + begin;
      for (std::size_t k = 0; k < count; ++k) nearest[k] = std::numeric_limits<double>::infinity();
      std::size_t within = 0;
      for (const Vec3& c : contacts) {
        for (std::size_t k = 0; k < count; ++k) {
          // squared_norm(position - c), as the queries and the band test compute it
          const double dx = static_cast<double>(x[k]) - c.x;
          const double dy = static_cast<double>(y[k]) - c.y;
          const double dz = static_cast<double>(z[k]) - c.z;
          const double d2 = dx * dx + dy * dy + dz * dz;
          within += d2 <= radius_squared ? 1 : 0;
          nearest[k] = d2 < nearest[k] ? d2 : nearest[k];
        }
      }
      found_last_ += within;
      if (!visit(begin, count)) {
        // Past the share that makes the frame global (build()), the rest of the scan could only
        // add to it: the frame is global already. What the balls found is extrapolated from the
        // points scanned, for scan_pays() to judge the next build by.
        const double scanned = static_cast<double>(begin + count);
        found_last_ = static_cast<std::size_t>(static_cast<double>(found_last_) * static_cast<double>(n) / scanned);
        return;
      }
    }
  };
  // After a build that went global for its share (a press over much of a small model, frame
  // after frame), the points are counted before they are listed: the count stops at the share
  // without writing a point, and the listing follows only when it stays below. The same points
  // and band either way; only the cost follows the last build.
  if (went_global_for_share_) {
    std::size_t held = 0;
    for_each_chunk([&](std::size_t, std::size_t count) {
      for (std::size_t k = 0; k < count; ++k) held += nearest[k] <= radius_squared ? 1 : 0;
      return !past_cheaper_share(held, n);
    });
    if (past_cheaper_share(held, n)) return true;
    found_last_ = 0;
  }
  for_each_chunk([&](std::size_t begin, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) {
      if (!(nearest[k] <= radius_squared)) continue;
      const auto i = static_cast<std::uint32_t>(begin + k);
      points_.push_back(i);
      if (!(nearest[k] <= inner_squared)) border_.push_back(i);
    }
    return !past_cheaper_share(points_.size(), n);
  });
  return false;
}

}  // namespace sculpt::deform
