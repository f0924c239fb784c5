#include "sculpt/hal/lcm_messages.hpp"

#include <cmath>
#include <cstddef>
#include <limits>

namespace sculpt::hal {
namespace {

template <std::size_t N>
bool all_finite(const float (&values)[N]) noexcept {
  for (float v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

template <std::size_t R, std::size_t C>
bool all_finite(const float (&values)[R][C]) noexcept {
  for (const auto& row : values) {
    if (!all_finite(row)) return false;
  }
  return true;
}

bool valid_hand(std::int8_t hand) noexcept { return hand >= 0 && static_cast<std::size_t>(hand) < hal::kHands; }

}  // namespace

void to_lcm(const hal::GloveSample& sample, std::int64_t utime, sculpt_lcm::glove_sample_t& out) noexcept {
  out.utime = utime;
  // A device clock beyond 2^63 us (292,000 years) is not a real clock; saturate rather than wrap.
  out.device_time_us = sample.device_time_us > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
                           ? std::numeric_limits<std::int64_t>::max()
                           : static_cast<std::int64_t>(sample.device_time_us);
  out.hand = static_cast<std::int8_t>(sample.hand);
  out.kind = static_cast<std::int8_t>(sample.kind);
  // LCM has no unsigned types: the counter travels as the same 32 bits.
  out.sequence = static_cast<std::int32_t>(sample.sequence);
  for (std::size_t j = 0; j < hal::kJointPoints; ++j) {
    for (std::size_t c = 0; c < 3; ++c) out.joints[j][c] = sample.joints[j][c];
  }
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t a = 0; a < 4; ++a) out.angles[f][a] = sample.angles[f][a];
  }
  for (std::size_t c = 0; c < 3; ++c) out.position[c] = sample.wrist.position[c];
  for (std::size_t c = 0; c < 4; ++c) out.orientation[c] = sample.wrist.orientation[c];
}

bool from_lcm(const sculpt_lcm::glove_sample_t& message, hal::GloveSample& out) noexcept {
  if (!valid_hand(message.hand)) return false;
  if (message.kind != sculpt_lcm::glove_sample_t::KIND_POSITIONS &&
      message.kind != sculpt_lcm::glove_sample_t::KIND_ANGLES) {
    return false;
  }
  if (message.device_time_us < 0) return false;
  if (!all_finite(message.joints) || !all_finite(message.angles) || !all_finite(message.position) ||
      !all_finite(message.orientation)) {
    return false;
  }
  out.hand = static_cast<std::uint8_t>(message.hand);
  out.kind = static_cast<hal::SampleKind>(message.kind);
  out.sequence = static_cast<std::uint32_t>(message.sequence);
  out.device_time_us = static_cast<std::uint64_t>(message.device_time_us);
  for (std::size_t j = 0; j < hal::kJointPoints; ++j) {
    for (std::size_t c = 0; c < 3; ++c) out.joints[j][c] = message.joints[j][c];
  }
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t a = 0; a < 4; ++a) out.angles[f][a] = message.angles[f][a];
  }
  for (std::size_t c = 0; c < 3; ++c) out.wrist.position[c] = message.position[c];
  for (std::size_t c = 0; c < 4; ++c) out.wrist.orientation[c] = message.orientation[c];
  return true;
}

void to_lcm(const hal::HapticCommand& command, std::int64_t utime, sculpt_lcm::haptic_command_t& out) noexcept {
  out.utime = utime;
  out.tick = command.tick;
  out.hand = static_cast<std::int8_t>(command.hand);
  out.active_mask = static_cast<std::int8_t>(command.active_mask);
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t c = 0; c < 3; ++c) out.force[f][c] = command.force[f][c];
  }
}

bool from_lcm(const sculpt_lcm::haptic_command_t& message, hal::HapticCommand& out) noexcept {
  constexpr unsigned kFingerBits = (1u << hal::kFingers) - 1u;
  if (!valid_hand(message.hand)) return false;
  if (message.tick < 0 || message.tick > std::numeric_limits<std::uint32_t>::max()) return false;
  if ((static_cast<std::uint8_t>(message.active_mask) & ~kFingerBits) != 0) return false;
  if (!all_finite(message.force)) return false;
  out.hand = static_cast<std::uint8_t>(message.hand);
  out.tick = static_cast<std::uint32_t>(message.tick);
  out.active_mask = static_cast<std::uint8_t>(message.active_mask);
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t c = 0; c < 3; ++c) out.force[f][c] = message.force[f][c];
  }
  return true;
}

}  // namespace sculpt::hal
