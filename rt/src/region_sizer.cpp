#include "sculpt/rt/region_sizer.hpp"

#include <algorithm>
#include <cmath>

namespace sculpt::rt {
namespace {

// The newest frame's weight in the average: about the last five frames count.
constexpr double kNewWeight = 0.2;

}  // namespace

void RegionSizer::observe(std::size_t region_points, std::size_t forces, double deform_ns) noexcept {
  const double x = static_cast<double>(region_points) * static_cast<double>(forces);
  if (!(x > 0.0) || !(deform_ns >= 0.0) || !std::isfinite(deform_ns)) return;
  const bool first = !ready();
  last_ns_ = deform_ns / x;
  average_ns_ = first ? last_ns_ : (1.0 - kNewWeight) * average_ns_ + kNewWeight * last_ns_;
}

double RegionSizer::next_radius(double radius, std::size_t region_points, std::size_t forces,
                                double budget_ns) const noexcept {
  if (!ready() || region_points == 0 || forces == 0) return radius;
  const double per_point_force_ns = std::max(average_ns_, last_ns_);
  const double target_points = budget_fraction_ * budget_ns / (per_point_force_ns * static_cast<double>(forces));
  const double ratio = target_points / static_cast<double>(region_points);
  // Written out rather than std::clamp so that a NaN budget shrinks too.
  return radius * std::sqrt(ratio > kMaxGrowth ? kMaxGrowth : (ratio > kMaxShrink ? ratio : kMaxShrink));
}

}  // namespace sculpt::rt
