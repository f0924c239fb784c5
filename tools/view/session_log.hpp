#pragma once
// What the viewer takes from a durable session log: the collision events (the edit history),
// the fingertips and the tick statistics, decoded with logging's own readers. Both --log
// playback and --catch-up read logs this way.

#include <cstdint>
#include <string>
#include <vector>

#include "frame_follower.hpp"
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

/// The log's events for frame ids [first, last], and whether it reaches past `last` (see
/// CatchUpResult): reread on each call, since the station is still appending to it.
CatchUpResult catch_up_from(const std::string& path, std::int64_t first, std::int64_t last);

}  // namespace sculpt::view
