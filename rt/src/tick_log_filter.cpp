#include "sculpt/rt/tick_log_filter.hpp"

#include <cmath>

namespace sculpt::rt {

TickLogFilter::TickLogFilter(std::uint64_t interval_ticks, double slow_us) noexcept
    : interval_ticks_(interval_ticks), slow_us_(slow_us) {}

bool TickLogFilter::keep(const TickReport& report, std::uint64_t overruns, std::uint64_t missed_periods,
                         double tick_time_us) noexcept {
  const bool eventful = report.collisions > 0 || report.guards.total() > 0 || overruns != last_overruns_ ||
                        missed_periods != last_missed_ || report.out_of_range != last_out_of_range_ ||
                        report.glove != last_glove_ || !(tick_time_us < slow_us_);
  const bool due = !any_kept_ || interval_ticks_ <= 1 || report.tick - last_tick_ >= interval_ticks_;
  if (!eventful && !due) {
    ++left_out_;
    return false;
  }
  any_kept_ = true;
  last_tick_ = report.tick;
  last_overruns_ = overruns;
  last_missed_ = missed_periods;
  last_out_of_range_ = report.out_of_range;
  last_glove_ = report.glove;
  ++kept_;
  return true;
}

std::uint64_t tick_log_interval(double interval_ms, double rate_hz) noexcept {
  const double ticks = std::round(interval_ms * rate_hz / 1000.0);
  return ticks >= 1.0 ? static_cast<std::uint64_t>(ticks) : 0;
}

}  // namespace sculpt::rt
