#pragma once
// Conversions between the hal's plain structs and their LCM messages. Outgoing conversions
// cannot fail; incoming ones validate every field and return false instead of throwing, so
// they are safe inside an LCM handler (handlers never throw). None of them allocates.

#include <cstdint>

#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "sculpt_lcm/glove_sample_t.hpp"
#include "sculpt_lcm/haptic_command_t.hpp"

namespace sculpt::hal {

/// Fills `out` from `sample`. `utime` is the host wall-clock time to stamp (microseconds since
/// the Unix epoch); the sample's receive_time_ns is host-local and is not sent.
void to_lcm(const hal::GloveSample& sample, std::int64_t utime, sculpt_lcm::glove_sample_t& out) noexcept;

/// Fills `out` from `message` when every field is valid: hand 0 or 1, a known kind, a
/// non-negative device time and finite floats throughout. Returns false, leaving `out`
/// unspecified, otherwise. `out.receive_time_ns` is left for the caller (the receive clock).
bool from_lcm(const sculpt_lcm::glove_sample_t& message, hal::GloveSample& out) noexcept;

/// Fills `out` from `command`, stamped with `utime` (microseconds since the Unix epoch).
void to_lcm(const hal::HapticCommand& command, std::int64_t utime, sculpt_lcm::haptic_command_t& out) noexcept;

/// Fills `out` from `message` when valid: hand 0 or 1, tick in [0, 2^32), no mask bit above
/// the little finger, finite forces. Returns false otherwise.
bool from_lcm(const sculpt_lcm::haptic_command_t& message, hal::HapticCommand& out) noexcept;

}  // namespace sculpt::hal
