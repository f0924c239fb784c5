#include "sculpt/rt/region_sizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sculpt::rt {
namespace {

// The newest frame's weight in the average: about the last five frames count.
constexpr double kNewWeight = 0.2;

}  // namespace

void RegionSizer::observe(std::size_t region_points, std::size_t forces, double deform_ns, bool global) noexcept {
  const double x = static_cast<double>(region_points) * static_cast<double>(forces);
  if (!(x > 0.0) || !(deform_ns >= 0.0) || !std::isfinite(deform_ns)) return;
  double& average = global ? global_average_ns_ : average_ns_;
  double& last = global ? global_last_ns_ : last_ns_;
  const bool first = !(average > 0.0 || last > 0.0);
  last = deform_ns / x;
  average = first ? last : (1.0 - kNewWeight) * average + kNewWeight * last;
}

double RegionSizer::next_radius(double radius, std::size_t region_points, std::size_t forces, double budget_ns,
                                std::size_t model_points) const noexcept {
  const double share = budget_fraction_ * budget_ns;
  const double f = static_cast<double>(forces);
  const double model = static_cast<double>(model_points);
  if (forces > 0 && (global_average_ns_ > 0.0 || global_last_ns_ > 0.0)) {
    // Seen: the global frame while its own cost fits the share.
    if (std::max(global_average_ns_, global_last_ns_) * model * f <= share) {
      return std::numeric_limits<double>::infinity();
    }
  } else if (ready() && forces > 0 && share / (std::max(average_ns_, last_ns_) * f) >= kGlobalTrial * model) {
    return std::numeric_limits<double>::infinity();  // not seen, and likely to fit: try one
  }
  if (!ready() || region_points == 0 || forces == 0) return radius;
  const double per_point_force_ns = std::max(average_ns_, last_ns_);
  const double target_points = share / (per_point_force_ns * f);
  const double ratio = target_points / static_cast<double>(region_points);
  // After a global frame that did not fit, straight down to the share: the shrink limit is for
  // a region's own noise, and every step from the whole model would be a frame over it.
  const double shrink = static_cast<double>(region_points) >= model ? 0.0 : kMaxShrink;
  // Written out rather than std::clamp so that a NaN budget shrinks too.
  return radius * std::sqrt(ratio > kMaxGrowth ? kMaxGrowth : (ratio > shrink ? ratio : shrink));
}

}  // namespace sculpt::rt
