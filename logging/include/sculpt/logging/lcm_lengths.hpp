#pragma once
// The lengths inside an LCM payload, checked before lcm-gen's decoder reads them.
//
// Why: the decoders lcm-gen writes trust a message's own lengths. In log_check_t's crc[count],
// a negative count makes decode() throw std::length_error from vector::resize, and a count past
// 2^29 first allocates up to 8 GiB and then overflows decode's int size check, so that it reads
// far past the payload. In a string, a length of zero or less makes decode() throw (or, at
// INT32_MIN, overflow an int). A damaged or hostile log must be damage at a byte offset, never
// a crash or a whole replay refused, so logging::decode walks the payload here first.
//
// Every message type is declared here as fixed-size or given a walk of its own: a new type
// that is neither does not compile where it is decoded, so it cannot slip past the check.

#include <cstdint>
#include <span>
#include <string>

namespace sculpt_lcm {
class collision_event_t;
class fingertip_state_t;
class glove_sample_t;
class haptic_command_t;
class log_check_t;
class session_header_t;
class tick_stats_t;
}  // namespace sculpt_lcm

namespace sculpt::logging {

/// Types with no array or string whose length the payload carries: decode() checks their size.
template <typename Message>
inline constexpr bool kFixedSizeMessage = false;
template <>
inline constexpr bool kFixedSizeMessage<sculpt_lcm::collision_event_t> = true;
template <>
inline constexpr bool kFixedSizeMessage<sculpt_lcm::fingertip_state_t> = true;
template <>
inline constexpr bool kFixedSizeMessage<sculpt_lcm::glove_sample_t> = true;
template <>
inline constexpr bool kFixedSizeMessage<sculpt_lcm::haptic_command_t> = true;
template <>
inline constexpr bool kFixedSizeMessage<sculpt_lcm::tick_stats_t> = true;

/// Empty when every length `payload` (a whole encoded message, fingerprint first) carries fits
/// what is left of it; else what does not, naming the field and its byte within the payload.
/// Fields past the last length are not looked at: decode() checks those against the size.
std::string payload_lengths_problem(const sculpt_lcm::log_check_t&, std::span<const std::uint8_t> payload);
std::string payload_lengths_problem(const sculpt_lcm::session_header_t&, std::span<const std::uint8_t> payload);

/// Any other type: one declared fixed-size has nothing to walk.
template <typename Message>
std::string payload_lengths_problem(const Message&, std::span<const std::uint8_t>) {
  static_assert(kFixedSizeMessage<Message>,
                "an LCM type with an array or string: give it a walk in lcm_lengths.cpp, or declare it fixed-size");
  return {};
}

}  // namespace sculpt::logging
