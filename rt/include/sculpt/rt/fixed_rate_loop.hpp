#pragma once
// The station's clock: one tick per period on absolute deadlines (CLOCK_MONOTONIC,
// clock_nanosleep with TIMER_ABSTIME), so lateness never accumulates into drift. A tick that
// runs past the next deadline is an overrun: the periods it covered are skipped, never
// replayed as a burst of catch-up ticks, and ticks resume on the original phase.

#include <atomic>
#include <cstdint>
#include <type_traits>

#include "sculpt/base/clock.hpp"
#include "sculpt/rt/latency_histogram.hpp"

namespace sculpt::rt {

/// The loop's clock is the host's monotonic clock (sculpt/base/clock.hpp).
using base::monotonic_now_ns;
using base::sleep_until_ns;
using base::thread_cpu_now_ns;

/// What one run of the loop did.
struct LoopStats {
  std::uint64_t ticks = 0;           ///< ticks called
  std::uint64_t overruns = 0;        ///< ticks that ended after the next deadline
  std::uint64_t missed_periods = 0;  ///< periods skipped because of overruns (no tick for them)
  LatencyHistogram tick_time;        ///< time used by each tick, wake-up to return (ns)
  /// CPU time the loop's thread spent in each tick (ns). Beside tick_time it tells a tick that
  /// worked long from one the kernel preempted (wall time grows, CPU time does not). Not one the
  /// hypervisor held up, unless the host reports steal time: these VMs report none (/proc/stat),
  /// so there that time is the thread's too.
  LatencyHistogram tick_cpu_time;
  LatencyHistogram wake_jitter;  ///< how late each wake-up was after its deadline (ns)
  std::int64_t started_ns = 0;   ///< CLOCK_MONOTONIC when run() started
  std::int64_t ended_ns = 0;     ///< CLOCK_MONOTONIC when run() saw the stop flag
};

/// Calls a tick once per period until stopped. Construction validates; run() is noexcept and
/// allocates nothing (the statistics live in the loop, with fixed storage).
class FixedRateLoop {
 public:
  static constexpr double kMinRateHz = 50.0;
  static constexpr double kMaxRateHz = 2000.0;

  /// @throw std::invalid_argument when rate_hz is not in [kMinRateHz, kMaxRateHz].
  explicit FixedRateLoop(double rate_hz);

  /// Runs until `stop` is true; returns within one period of it being set (plus the tick in
  /// progress). Tick k is called as tick(k, deadline_ns) with k = 0, 1, 2, ... counting ticks
  /// and deadline_ns its absolute CLOCK_MONOTONIC deadline; deadlines are first + m * period
  /// for whole m, so a tick can tell skipped periods from the deadlines. The first deadline is
  /// one period after the call. The tick must be noexcept (checked at compile time): the loop
  /// has no way to recover from an exception half-way through a tick. Statistics are reset at
  /// the start and readable through stats() after return.
  template <typename Tick>
  void run(Tick&& tick, const std::atomic<bool>& stop) noexcept {
    static_assert(std::is_nothrow_invocable_v<Tick&, std::uint64_t, std::int64_t>,
                  "FixedRateLoop: the tick must be callable as tick(uint64_t, int64_t) and noexcept");
    std::int64_t deadline = begin_run() + period_ns_;
    while (!stop.load(std::memory_order_acquire)) {
      sleep_until_ns(deadline);
      const std::int64_t woke = monotonic_now_ns();
      // Checked again after the sleep, so a stop set during it costs no extra tick.
      if (stop.load(std::memory_order_acquire)) break;
      const std::int64_t woke_cpu = thread_cpu_now_ns();
      tick(stats_.ticks, deadline);
      deadline = end_tick(deadline, woke, woke_cpu);
    }
    stats_.ended_ns = monotonic_now_ns();
  }

  /// The statistics of the last (or current) run.
  const LoopStats& stats() const noexcept { return stats_; }
  /// Ticks per second over the last run: ticks / (end - start), wall time on CLOCK_MONOTONIC,
  /// from the start of run() to its return. 0 before any run.
  double achieved_rate() const noexcept;
  double rate_hz() const noexcept { return rate_hz_; }
  std::int64_t period_ns() const noexcept { return period_ns_; }

 private:
  // Resets the statistics; returns the start time.
  std::int64_t begin_run() noexcept;
  // Accounts one tick that woke at `woke` (and at `woke_cpu` on the thread's CPU clock) for
  // `deadline`; returns the next deadline that is still in the future, counting an overrun and
  // the periods skipped to reach it.
  std::int64_t end_tick(std::int64_t deadline, std::int64_t woke, std::int64_t woke_cpu) noexcept;

  double rate_hz_;
  std::int64_t period_ns_;
  LoopStats stats_;
};

}  // namespace sculpt::rt
