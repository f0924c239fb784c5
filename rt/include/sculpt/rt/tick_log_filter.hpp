#pragma once
// Which loop ticks the durable log keeps. At 1 kHz a record per tick was three quarters of a
// session's log: 6.8 MB a minute while the station idled, about 400 MB an hour, each quiet tick
// saying what the one before it said. Kept: every tick in which something happened (a
// collision, a guard acting, an overrun or missed period, the glove's state changing, a
// fingertip dropped, a tick taking half the period or more), and one at least every
// `interval_ticks`, so the log still shows the loop alive and its counters moving. The live
// channel carries every tick; replay and transfer never read ticks.

#include <cstdint>

#include "sculpt/rt/station.hpp"

namespace sculpt::rt {

class TickLogFilter {
 public:
  /// `interval_ticks` 0 or 1 keeps every tick. `slow_us`: a tick at least this long is kept.
  TickLogFilter(std::uint64_t interval_ticks, double slow_us) noexcept;

  /// Whether the durable log keeps this tick; counts it either way. Called once per tick, in
  /// order; allocates nothing.
  bool keep(const TickReport& report, std::uint64_t overruns, std::uint64_t missed_periods,
            double tick_time_us) noexcept;

  std::uint64_t kept() const noexcept { return kept_; }
  std::uint64_t left_out() const noexcept { return left_out_; }

 private:
  std::uint64_t interval_ticks_;
  double slow_us_;
  bool any_kept_ = false;
  std::uint64_t last_tick_ = 0;
  std::uint64_t last_overruns_ = 0;
  std::uint64_t last_missed_ = 0;
  std::uint64_t last_out_of_range_ = 0;
  GloveState last_glove_ = GloveState::kWaiting;
  std::uint64_t kept_ = 0;
  std::uint64_t left_out_ = 0;
};

/// The interval in ticks for `interval_ms` at `rate_hz` (0: every tick).
std::uint64_t tick_log_interval(double interval_ms, double rate_hz) noexcept;

}  // namespace sculpt::rt
