#pragma once
// What the viewer takes from a durable session log: the collision events (the edit history),
// the fingertips and the tick statistics, decoded with logging's own readers. Both --log
// playback and --catch-up read logs this way.

#include <cstdint>
#include <string>
#include <vector>

#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/records.hpp"
#include "view_state.hpp"

namespace sculpt::view {

struct SessionLog {
  std::vector<logging::CollisionRecord> collisions;  ///< in log order
  std::vector<FingertipSeen> fingertips;
  std::vector<TickSeen> ticks;
  std::size_t damaged = 0;  ///< places that were not a valid event, or did not decode
};

/// Reads the whole log at `path` (going on past damage). @throw logging::LogFileError when it
/// cannot be read at all.
SessionLog read_session_log(const std::string& path);

/// One SCULPT_COLLISION event's record; false when its payload does not decode.
bool collision_from(const logging::LogEvent& event, logging::CollisionRecord& out);

}  // namespace sculpt::view
