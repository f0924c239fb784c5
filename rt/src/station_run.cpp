#include "sculpt/rt/station_run.hpp"

namespace sculpt::rt {

void run_station(Station& station, FixedRateLoop& loop, StationRecorder* recorder, LiveStatus& live,
                 std::int64_t end_ns, std::atomic<bool>& stop) noexcept {
  const std::int64_t period = loop.period_ns();
  loop.run(
      [&](std::uint64_t, std::int64_t deadline) noexcept {
        const std::int64_t now = monotonic_now_ns();
        const TickReport& r = station.tick(now, deadline + period - now);
        const LoopStats& stats = loop.stats();
        if (recorder) {
          recorder->tick(r, stats.overruns, stats.missed_periods, static_cast<double>(monotonic_now_ns() - now) * 1e-3);
        }
        live.ticks.store(r.tick + 1, std::memory_order_relaxed);
        live.overruns.store(stats.overruns, std::memory_order_relaxed);
        live.collisions.fetch_add(r.collisions, std::memory_order_relaxed);
        if (r.frame) {
          live.region_points.store(r.region_points, std::memory_order_relaxed);
          live.deform_ns.store(static_cast<std::uint64_t>(r.deform_ns), std::memory_order_relaxed);
        }
        live.samples.fetch_add(r.samples, std::memory_order_relaxed);
        live.glove.store(static_cast<int>(r.glove), std::memory_order_relaxed);
        if (now >= end_ns) stop.store(true, std::memory_order_release);
      },
      stop);
}

}  // namespace sculpt::rt
