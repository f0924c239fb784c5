#include "sculpt/deform/region.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::deform {

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
  for (const Vec3& c : contacts) {
    index.within_radius(model, c, settings_.radius, scratch_, drift);
    for (std::uint32_t i : scratch_) {
      if (!member_[i]) {
        member_[i] = 1;
        points_.push_back(i);
      }
    }
  }
  std::sort(points_.begin(), points_.end());
  // A point is in the band when it is not deeper than the border width inside any ball.
  const double inner = settings_.radius - border_width_;
  for (std::uint32_t i : points_) {
    member_[i] = 0;
    const Vec3 q = model.position(i);
    const bool deep =
        std::any_of(contacts.begin(), contacts.end(), [&](const Vec3& c) { return norm(q - c) <= inner; });
    if (!deep) border_.push_back(i);
  }
}

}  // namespace sculpt::deform
