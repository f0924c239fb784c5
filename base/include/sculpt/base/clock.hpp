#pragma once
// The host's clocks, read once here rather than by every backend. Each is noexcept and
// allocation-free, so the loop and the I/O threads may read them; all but the thread's CPU
// clock are vDSO calls.

#include <cstdint>

namespace sculpt::base {

/// CLOCK_MONOTONIC in nanoseconds: the station's time base. Never leaves the host.
std::int64_t monotonic_now_ns() noexcept;
/// CLOCK_MONOTONIC in microseconds (device_time_us stamps of host-made frames).
inline std::uint64_t monotonic_now_us() noexcept { return static_cast<std::uint64_t>(monotonic_now_ns() / 1000); }
/// Sleeps until CLOCK_MONOTONIC reaches `deadline_ns` (at once if it has passed); a signal
/// does not cut the sleep short.
void sleep_until_ns(std::int64_t deadline_ns) noexcept;
/// CLOCK_REALTIME in microseconds since the Unix epoch: the only time that goes on the wire
/// and into logs (lcm-logplayer paces by it, and other hosts can read it).
std::int64_t wall_time_us() noexcept;
/// CPU time the calling thread has used, in nanoseconds (CLOCK_THREAD_CPUTIME_ID): what a tick
/// cost the core, without the time the machine gave the core to something else. A system
/// call, not vDSO (about 0.1-0.3 us here), that never blocks.
std::int64_t thread_cpu_now_ns() noexcept;

}  // namespace sculpt::base
