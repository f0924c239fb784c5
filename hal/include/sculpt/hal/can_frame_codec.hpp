#pragma once
// The glove's messages on a CAN bus (classic 8-byte or CAN FD 64-byte frames): glove samples
// split into segments with a whole-message CRC-32, and haptic commands. docs/glove-can.md is
// the wire specification; this file is its only implementation. Pure computation: no sockets,
// no allocation, nothing throws, so it is tested everywhere and reusable by any CAN transport.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"

namespace sculpt::hal {

/// One CAN or CAN FD frame as the codec sees it. `id` is the arbitration id (11-bit, or 29-bit
/// when it does not fit 11 bits); `len` the data length in bytes (classic 0..8; FD one of
/// 0..8, 12, 16, 20, 24, 32, 48, 64).
struct CanFrame {
  std::uint32_t id = 0;
  std::uint8_t len = 0;
  bool fd = false;
  std::array<std::uint8_t, 64> data{};
};

inline constexpr std::uint32_t kCanHandStride = 0x40;                   ///< sample ids: base + hand * 0x40 + segment
inline constexpr std::uint32_t kCanHapticOffset = 0x80;                 ///< haptic ids: base + 0x80 + hand
inline constexpr std::uint32_t kCanIdSpan = kCanHapticOffset + kHands;  ///< ids used from base
inline constexpr std::uint32_t kCanMaxStandardId = 0x7FF;
inline constexpr std::uint32_t kCanMaxExtendedId = 0x1FFFFFFF;
inline constexpr std::size_t kCanClassicLen = 8;
inline constexpr std::size_t kCanFdLen = 64;
/// Frames of the largest message (a positions sample over classic CAN).
inline constexpr std::size_t kCanMaxSampleFrames = 35;
/// Frames of a haptic command over classic CAN (2 over CAN FD).
inline constexpr std::size_t kCanMaxHapticFrames = 10;
/// Bytes of a message (payload + CRC-32) buffered by a decoder; the largest is 245.
inline constexpr std::size_t kCanMaxMessage = 256;

/// CRC-32 (IEEE 802.3 / zlib: reflected polynomial 0xEDB88320, initial and final xor
/// 0xFFFFFFFF) of `bytes`.
std::uint32_t can_crc32(std::span<const std::uint8_t> bytes) noexcept;

/// The smallest valid CAN FD data length >= n (n <= 64).
std::uint8_t can_fd_round_up(std::size_t n) noexcept;

/// Bytes of a sample message of this kind, CRC included (245 positions, 125 angles); 0 for an
/// unknown kind.
std::size_t can_sample_message_size(SampleKind kind) noexcept;
/// Bytes of a haptic message, CRC included.
inline constexpr std::size_t kCanHapticMessageSize = 69;
/// Frames needed for a message of `message_size` bytes: each frame carries one header byte.
std::size_t can_segment_count(std::size_t message_size, bool fd) noexcept;

/// Encodes `sample` into frames `out[0..n)` and returns n; returns 0 (writing nothing useful)
/// when `out` is too small, the hand is not 0..1, the kind is unknown, or the ids would pass
/// the 29-bit range.
std::size_t encode_sample(const GloveSample& sample, std::uint32_t base_id, bool fd, std::span<CanFrame> out) noexcept;

/// Encodes a haptic command (ids base + 0x80 + hand) as encode_sample does.
std::size_t encode_haptic(const HapticCommand& command, std::uint32_t base_id, bool fd,
                          std::span<CanFrame> out) noexcept;

/// What one frame did to a decoder.
enum class CanFeedResult : std::uint8_t {
  kIgnored,       ///< not one of this decoder's ids: someone else's traffic
  kPending,       ///< a segment accepted, the message is not complete yet
  kDuplicate,     ///< a repeat of the segment just accepted (CAN may retransmit): dropped
  kComplete,      ///< the message is complete, its CRC matched, `out` is written
  kFramingError,  ///< malformed, out of order or missing segments: the message is dropped
  kCrcError,      ///< all segments arrived but the CRC did not match: the message is dropped
  kDiscarded,     ///< a later segment of a message already dropped (not counted again)
};

/// Traffic and fault counts of one decoder. Each broken message counts one framing or CRC
/// error, however many of its frames are lost.
struct CanDecoderCounters {
  std::uint64_t frames = 0;    ///< frames addressed to this decoder
  std::uint64_t messages = 0;  ///< messages completed with a good CRC
  std::uint64_t framing_errors = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t duplicates = 0;
  std::uint64_t discarded = 0;      ///< frames dropped after their message was already broken
  std::uint64_t sequence_gaps = 0;  ///< samples missing by sequence number (sample decoder only)
};

/// Reassembles one stream of segmented messages (one hand's samples, or one hand's haptic
/// commands). Shared by the two decoders below; fixed-size, allocation-free.
class CanReassembler {
 public:
  /// `sample_ids`: a sample stream, whose segment index is also the id's offset from
  /// `first_id` and whose size follows from its first byte (the kind); otherwise a haptic
  /// stream, every segment on `first_id`, kCanHapticMessageSize bytes.
  CanReassembler(std::uint32_t first_id, bool sample_ids, bool fd) noexcept;

  /// Feeds one frame. On kComplete, message() holds the payload (CRC stripped).
  CanFeedResult feed(const CanFrame& frame) noexcept;

  /// The last completed message's payload, CRC excluded.
  std::span<const std::uint8_t> message() const noexcept { return {buffer_.data(), payload_size_}; }
  const CanDecoderCounters& counters() const noexcept { return counters_; }
  CanDecoderCounters& counters() noexcept { return counters_; }
  /// Forgets any partial message (counters are kept).
  void reset() noexcept;

 private:
  enum class State : std::uint8_t { kIdle, kAssembling, kDiscarding };
  CanFeedResult broken(CanFeedResult why) noexcept;
  bool is_duplicate(const CanFrame& frame, unsigned index, unsigned seq) const noexcept;

  std::uint32_t first_id_;
  bool sample_ids_;
  bool fd_;
  std::size_t chunk_;
  State state_ = State::kIdle;
  std::array<std::uint8_t, kCanMaxMessage> buffer_{};
  std::size_t message_size_ = 0;  // bytes expected, CRC included
  std::size_t payload_size_ = 0;  // of the last completed message
  unsigned next_index_ = 0;
  unsigned seq_bits_ = 0;
  bool have_last_ = false;  // last_index_ names a segment still in buffer_
  unsigned last_index_ = 0;
  CanDecoderCounters counters_;
};

/// Decodes one hand's glove samples.
class CanSampleDecoder {
 public:
  CanSampleDecoder(std::uint32_t base_id, std::uint8_t hand, bool fd) noexcept;
  /// Feeds one frame; on kComplete `out` is the sample (receive_time_ns left 0 for the
  /// caller to stamp). A message whose CRC matches but whose content is invalid (non-finite
  /// numbers) is a framing error.
  CanFeedResult feed(const CanFrame& frame, GloveSample& out) noexcept;
  const CanDecoderCounters& counters() const noexcept { return reassembler_.counters(); }
  void reset() noexcept;

 private:
  std::uint8_t hand_;
  CanReassembler reassembler_;
  bool have_sequence_ = false;
  std::uint32_t next_sequence_ = 0;
};

/// Decodes one hand's haptic commands (for a device, a bridge or a test).
class CanHapticDecoder {
 public:
  CanHapticDecoder(std::uint32_t base_id, std::uint8_t hand, bool fd) noexcept;
  CanFeedResult feed(const CanFrame& frame, HapticCommand& out) noexcept;
  const CanDecoderCounters& counters() const noexcept { return reassembler_.counters(); }
  void reset() noexcept { reassembler_.reset(); }

 private:
  std::uint8_t hand_;
  CanReassembler reassembler_;
};

}  // namespace sculpt::hal
