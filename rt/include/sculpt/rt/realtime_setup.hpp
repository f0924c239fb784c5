#pragma once
// Asking the OS for real-time treatment of the loop thread. Each request may be refused
// (no CAP_SYS_NICE, no CAP_IPC_LOCK, a CPU that is not there, a container): the station then
// runs anyway, best effort, and says what it did not get.

#include <string>
#include <vector>

namespace sculpt::rt {

/// What to ask for. The defaults ask for nothing.
struct RealtimeOptions {
  /// SCHED_FIFO for the calling thread at `priority`.
  bool fifo = false;
  /// SCHED_FIFO priority, within sched_get_priority_min/max(SCHED_FIFO) (1..99 on Linux).
  int priority = 80;
  /// mlockall(MCL_CURRENT | MCL_FUTURE) for the whole process: no page faults in the loop.
  bool lock_memory = false;
  /// Pin the calling thread to this CPU; -1 leaves the affinity alone.
  int cpu = -1;
  /// prctl(PR_SET_TIMERSLACK, 1 ns) for the calling thread. A normal thread's sleeps may end
  /// up to 50 us late by default (the kernel batches wake-ups); measured here at 1 kHz, the
  /// median wake-up lateness went from 84 us to 38 us. Needs no privilege, so it is the
  /// fallback that still works when SCHED_FIFO is refused (FIFO threads have no slack).
  bool tight_timer_slack = false;
};

/// Applies `options` to the calling thread (scheduling, affinity, timer slack) and process
/// (memory lock).
/// Set-up only: allocates. Returns one warning per request the system refused, naming the
/// request and the reason (empty: everything granted). Refusals, EPERM included, are never
/// exceptions: a developer machine must be able to run the station.
/// @throw std::invalid_argument for options that cannot be right on any system: a priority
///        outside the SCHED_FIFO range when fifo is asked for, or cpu < -1 or beyond CPU_SETSIZE.
std::vector<std::string> apply_realtime(const RealtimeOptions& options);

/// Of apply_realtime's warnings, the first that a station which requires real time cannot run
/// with (SCHED_FIFO or the memory lock refused), or empty.
std::string required_refusal(const std::vector<std::string>& warnings);

}  // namespace sculpt::rt
