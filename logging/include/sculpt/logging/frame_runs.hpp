#pragma once
// A collision log's frames. One tick's solve writes its events consecutively under one
// frame_id, each saying how many the frame holds (frame_size); damage or a cut can leave a
// frame short. Replay, undo and the viewer agree on what a whole frame is through these.

#include <cstddef>
#include <span>

#include "sculpt/logging/records.hpp"

namespace sculpt::logging {

/// End (one past) of the run of consecutive events sharing events[begin]'s frame id.
std::size_t frame_run_end(std::span<const CollisionRecord> events, std::size_t begin) noexcept;

/// True when every event of `run` says its frame holds exactly run.size() events.
bool whole_frame(std::span<const CollisionRecord> run) noexcept;

}  // namespace sculpt::logging
