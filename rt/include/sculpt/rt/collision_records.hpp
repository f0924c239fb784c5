#pragma once
// The one place a deformation frame becomes collision events: the station's recorder (in the
// loop) and transfer's re-run (offline) both call frame_collision_records, so the log a
// session writes and the log a re-run writes are built by the same code.

#include <cstddef>
#include <span>

#include "sculpt/logging/records.hpp"
#include "sculpt/rt/station_recorder.hpp"

namespace sculpt::rt {

/// The records of one applied frame: one per collided probe, in probe order, sharing
/// frame.frame_id, written to the front of `out`. Nothing is written when the frame moved
/// nothing (no collision, or no finite solution: replaying it must not move anything either).
/// Each record holds what re-applies it without collision detection (the probe after the
/// frame, contact, source, force, weights, the settings in force) and its finger, taken from
/// frame.fingers when that names one per contact (hand and finger 0 otherwise). `utime` is
/// left 0 for the caller's clock. At most out.size() records are written; returns how many.
/// An index-set region cannot be recorded (a log holds a centre and radius): the station
/// never has one, and append_frame_records (transfer.hpp) refuses it before calling this.
/// noexcept and allocation-free: it runs inside the tick.
std::size_t frame_collision_records(const FrameRecord& frame, std::span<logging::CollisionRecord> out) noexcept;

}  // namespace sculpt::rt
