#pragma once
// The station's recorder for a session: every sample, fingertip, collision, haptic command and
// tick goes to the durable log (when the scene names one) and to the live channels (when it
// asks to publish). The loop's side only queues; the writing happens on the log's and the
// publisher's own threads.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/session_header.hpp"
#include "sculpt/rt/station_recorder.hpp"

namespace sculpt::rt {

/// What a recorder has written and lost so far, for the run's summary.
struct RecordingCounts {
  bool logging = false;  ///< a durable log is written
  std::string log_path;
  std::uint64_t glove_samples = 0, fingertips = 0, collisions = 0, ticks = 0, haptic = 0;
  std::uint64_t ticks_left_out = 0;  ///< quiet ticks the log did not keep (TickLogFilter)
  std::uint64_t log_dropped = 0, write_errors = 0;
  std::uint64_t log_checks = 0;  ///< SCULPT_CHECK events written (logging/event_check.hpp)
  bool publishing = false;       ///< the live channels are published
  std::uint64_t live_fingertips = 0, live_collisions = 0, live_ticks = 0, live_dropped = 0;
};

class SessionRecorder : public StationRecorder {
 public:
  /// Opens the log (replacing an earlier one at its path), writes and syncs its header, and
  /// starts the writer threads. Throws when the log cannot be written.
  virtual void start() = 0;
  /// Drains, flushes and closes: nothing queued is lost. Idempotent.
  virtual void stop() = 0;
  /// Pushes what is written so far to the kernel (a crash then loses nothing older).
  virtual void flush() = 0;
  virtual RecordingCounts counts() const = 0;
};

/// nullptr when the scene names neither a log nor live publishing. The log's path is locked
/// here but left as it was until start(), which writes `header` (when given) as its first event:
/// a station whose glove fails to start, between the two, keeps an earlier log. Throws
/// std::runtime_error with a clear message when the scene asks for a log or publishing and this
/// build has no LCM, and whatever the log's or the publisher's set-up throws.
std::unique_ptr<SessionRecorder> make_session_recorder(const Scene& scene,
                                                       const std::optional<SessionHeader>& header = std::nullopt);

}  // namespace sculpt::rt
