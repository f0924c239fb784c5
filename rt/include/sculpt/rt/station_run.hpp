#pragma once
// The station's whole tick as the loop runs it: the station's tick, its statistics to the
// recorder, and the figures the status line shows. `sculpt run` is a shell around this.

#include <atomic>
#include <cstdint>

#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/station.hpp"
#include "sculpt/rt/station_recorder.hpp"

namespace sculpt::rt {

/// What a status line shows, published by the loop with relaxed atomics: the loop never
/// prints, and whoever prints never touches the station.
struct LiveStatus {
  std::atomic<std::uint64_t> ticks{0}, overruns{0}, collisions{0}, region_points{0}, samples{0}, deform_ns{0};
  std::atomic<int> glove{0};  ///< a GloveState
};

/// Runs `station` on `loop` until `stop` is set or the monotonic clock passes `end_ns` (then
/// `stop` is set). Each tick gets the time left to its deadline as its budget and reports to
/// `recorder` (when not null) and `live`. Nothing here throws, allocates, locks or prints.
void run_station(Station& station, FixedRateLoop& loop, StationRecorder* recorder, LiveStatus& live,
                 std::int64_t end_ns, std::atomic<bool>& stop) noexcept;

}  // namespace sculpt::rt
