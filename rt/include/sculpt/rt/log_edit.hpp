#pragma once
// Editing the edit history: a session's collision events cut to what a crash left whole, cut at
// a frame, or without one stroke. Base model + edited events, transferred, is the model the
// edit describes (undo from the log, ARCHITECTURE.md "The log is the edit history").

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/logging/records.hpp"

namespace sculpt::rt {

/// The longest prefix of a log's events made of whole frames (consecutive events sharing a
/// frame_id, exactly as many as each one's frame_size says).
struct WholeFrames {
  std::size_t events = 0;        ///< events in the prefix
  std::size_t frames = 0;        ///< frames in the prefix
  std::int64_t last_frame = -1;  ///< id of the prefix's last frame; -1 when it is empty
  /// What follows the prefix is one last frame with fewer events than its frame_size: what a
  /// log cut at its end (SIGKILL, power cut) leaves. False when nothing follows, or when the
  /// first bad frame is followed by more events (damage inside the log).
  bool cut_at_end = false;
};

WholeFrames whole_frames(std::span<const logging::CollisionRecord> events) noexcept;

/// Every run of consecutive same-frame events whose count matches its frame_size, in order;
/// the others (frames damage left incomplete anywhere in the log) are left out.
std::vector<logging::CollisionRecord> drop_incomplete_frames(std::span<const logging::CollisionRecord> events);

/// The events of the frames up to and including `last_frame`.
std::vector<logging::CollisionRecord> until_frame(std::span<const logging::CollisionRecord> events,
                                                  std::int64_t last_frame);

/// One finger's contact from touch to release: the consecutive frames in which that finger
/// (hand, finger) has a collision event. A gap in its frame ids ends the stroke.
struct Stroke {
  std::size_t number = 0;  ///< 1-based, in the order the strokes began
  std::uint8_t hand = 0;
  std::uint8_t finger = 0;
  std::int64_t first_frame = 0;
  std::int64_t last_frame = 0;
  std::size_t events = 0;
};

/// The strokes of a log, numbered in the order their first events appear.
std::vector<Stroke> list_strokes(std::span<const logging::CollisionRecord> events);

/// The log without `stroke`'s events; every frame that lost one says so in a frame_size reduced
/// by as many, and a frame left with none disappears. Transferring the result is the session as
/// if that finger had never touched the model during the stroke (the other fingers' logged
/// forces are kept as they were solved).
std::vector<logging::CollisionRecord> drop_stroke(std::span<const logging::CollisionRecord> events,
                                                  const Stroke& stroke);

}  // namespace sculpt::rt
