#include "sculpt/rt/fixed_rate_loop.hpp"

#include <cerrno>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::rt {

FixedRateLoop::FixedRateLoop(double rate_hz) : rate_hz_(rate_hz), period_ns_(0) {
  if (!(rate_hz >= kMinRateHz && rate_hz <= kMaxRateHz)) {
    throw std::invalid_argument("fixed-rate loop: the rate must be " + base::number_text(kMinRateHz) + " to " +
                                base::number_text(kMaxRateHz) + " Hz, got " + base::number_text(rate_hz));
  }
  period_ns_ = std::llround(1e9 / rate_hz);
}

double FixedRateLoop::achieved_rate() const noexcept {
  const std::int64_t elapsed = stats_.ended_ns - stats_.started_ns;
  if (stats_.ticks == 0 || elapsed <= 0) return 0.0;
  return static_cast<double>(stats_.ticks) * 1e9 / static_cast<double>(elapsed);
}

std::int64_t FixedRateLoop::begin_run() noexcept {
  stats_.ticks = 0;
  stats_.overruns = 0;
  stats_.missed_periods = 0;
  stats_.tick_time.clear();
  stats_.tick_cpu_time.clear();
  stats_.wake_jitter.clear();
  stats_.started_ns = monotonic_now_ns();
  stats_.ended_ns = stats_.started_ns;
  return stats_.started_ns;
}

std::int64_t FixedRateLoop::end_tick(std::int64_t deadline, std::int64_t woke, std::int64_t woke_cpu) noexcept {
  const std::int64_t done_cpu = thread_cpu_now_ns();
  const std::int64_t done = monotonic_now_ns();
  ++stats_.ticks;
  stats_.wake_jitter.add(woke - deadline);
  stats_.tick_time.add(done - woke);
  stats_.tick_cpu_time.add(done_cpu - woke_cpu);
  std::int64_t next = deadline + period_ns_;
  if (done >= next) {
    // Every deadline in [next, done] has passed with no tick: skip them all and keep the phase.
    const std::int64_t missed = (done - next) / period_ns_ + 1;
    ++stats_.overruns;
    stats_.missed_periods += static_cast<std::uint64_t>(missed);
    next += missed * period_ns_;
  }
  return next;
}

}  // namespace sculpt::rt
