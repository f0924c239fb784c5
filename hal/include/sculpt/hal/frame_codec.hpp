#pragma once
// The glove wire protocol (docs/glove-protocol.md): COBS-framed, CRC-32-checked, little-endian
// frames carrying glove samples (glove to host) and haptic commands (host to glove). Shared by
// every byte-stream transport: serial, USB, CAN reassembly.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"

namespace sculpt::hal {

/// Largest encoded frame, including the COBS overhead and the 0x00 delimiter. Encoders need an
/// output buffer this big; the decoder drops anything longer as a framing error.
inline constexpr std::size_t kMaxFrameBytes = 512;

/// The protocol version this code speaks (the first body byte).
inline constexpr std::uint8_t kProtocolVersion = 1;

/// Frame type codes (the second body byte).
enum class FrameType : std::uint8_t { kPositions = 1, kAngles = 2, kHaptic = 3 };

/// Body sizes before COBS, from the version byte to the CRC inclusive.
inline constexpr std::size_t kFrameHeaderBytes = 16;  ///< version, type, hand, flags, sequence, time
inline constexpr std::size_t kFrameCrcBytes = 4;
inline constexpr std::size_t kPositionsBodyBytes = kFrameHeaderBytes + kJointPoints * 3 * 4 + kFrameCrcBytes;
inline constexpr std::size_t kAnglesBodyBytes = kFrameHeaderBytes + (kFingers * 4 + 3 + 4) * 4 + kFrameCrcBytes;
inline constexpr std::size_t kHapticBodyBytes = kFrameHeaderBytes + 1 + 4 + kFingers * 3 * 4 + kFrameCrcBytes;

/// One frame as decoded. `sample` is filled for kSample (receive_time_ns left 0 for the
/// transport to stamp), `haptic` for kHaptic; sequence and device_time_us for both.
struct DecodedFrame {
  enum class Type : std::uint8_t { kSample, kHaptic } type = Type::kSample;
  GloveSample sample;
  HapticCommand haptic;
  std::uint32_t sequence = 0;
  std::uint64_t device_time_us = 0;
};

/// What a FrameDecoder has seen since construction (reset() keeps them).
struct DecoderCounters {
  std::uint64_t frames = 0;          ///< frames accepted and delivered
  std::uint64_t crc_errors = 0;      ///< well-formed frames whose CRC-32 did not match
  std::uint64_t framing_errors = 0;  ///< invalid COBS, over-long, wrong length, unknown version
                                     ///< or type, hand out of range, non-finite floats
  std::uint64_t bytes_skipped = 0;   ///< bytes of rejected frames, their delimiters included
};

/// Encodes a glove sample (kPositions: joints; kAngles: angles and wrist) into `out`, whose
/// size must be at least kMaxFrameBytes. Returns the bytes written (COBS and the trailing 0x00),
/// or 0 when `out` is too small. Fields are written as given: a non-finite value or a hand out
/// of range makes a frame that receivers reject.
std::size_t encode_sample_frame(const GloveSample& s, std::span<std::uint8_t> out) noexcept;

/// Encodes a host-to-glove haptic command, like encode_sample_frame. `sequence` is the
/// sender's own frame counter, `device_time_us` the sender's clock.
std::size_t encode_haptic_frame(const HapticCommand& c, std::uint32_t sequence, std::uint64_t device_time_us,
                                std::span<std::uint8_t> out) noexcept;

/// Stream decoder. Feed it bytes in any chunking; it delivers each valid frame once and counts
/// every rejected one. After garbage it resynchronises on the next 0x00. Empty frames (0x00
/// right after 0x00) are idle fill, neither frames nor errors. Fixed internal buffers: no
/// allocation, ever. Not thread-safe: one decoder per byte stream.
class FrameDecoder {
 public:
  /// Decodes `bytes`, calling on_frame(const DecodedFrame&) for each valid frame, in order.
  /// on_frame must not throw. The DecodedFrame is only valid during the call.
  template <typename OnFrame>
  void feed(std::span<const std::uint8_t> bytes, OnFrame&& on_frame) noexcept;

  /// Counters since construction.
  const DecoderCounters& counters() const noexcept { return counters_; }

  /// Drops a partial frame (its bytes count as skipped, not as an error), e.g. after a
  /// reconnect, so the first bytes of the new connection are not glued to the old ones.
  void reset() noexcept;

 private:
  /// Handles a 0x00: decodes the bytes gathered since the last one. True when frame_ holds a
  /// valid frame to deliver.
  bool end_of_frame() noexcept;
  /// A byte arrived with the buffer full: drop the frame and skip to the next delimiter.
  void overflow() noexcept;

  std::array<std::uint8_t, kMaxFrameBytes - 1> encoded_{};  // the delimiter is never stored
  std::array<std::uint8_t, kMaxFrameBytes - 1> body_{};
  std::size_t length_ = 0;
  bool skipping_ = false;  // after an over-long frame, until the next delimiter
  DecodedFrame frame_;
  DecoderCounters counters_;
};

template <typename OnFrame>
void FrameDecoder::feed(std::span<const std::uint8_t> bytes, OnFrame&& on_frame) noexcept {
  for (const std::uint8_t b : bytes) {
    if (b != 0) {
      if (skipping_) {
        ++counters_.bytes_skipped;
      } else if (length_ < encoded_.size()) {
        encoded_[length_++] = b;
      } else {
        overflow();
      }
      continue;
    }
    if (end_of_frame()) on_frame(static_cast<const DecodedFrame&>(frame_));
  }
}

}  // namespace sculpt::hal
