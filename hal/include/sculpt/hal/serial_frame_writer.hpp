#pragma once
// The glove's end of a serial line: writes sample frames and counts the haptic frames that
// come back. Used by `sculpt glove-sim` to stand in for a glove, and by the tests.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "sculpt/hal/frame_codec.hpp"
#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "sculpt/hal/serial_port.hpp"

namespace sculpt::hal {

/// Opens a serial device (a pty slave, or a USB-serial adapter wired to the host) and writes
/// glove frames to it. Single-threaded; the I/O calls are noexcept and do not allocate.
class SerialFrameWriter {
 public:
  /// How long write_sample waits for room on the device before giving up.
  static constexpr int kWriteTimeoutMs = 1000;

  /// Opens `device` at `baud`.
  /// @throw std::invalid_argument for a non-standard baud
  /// @throw std::runtime_error "serial <device>: <step>: <reason>" when it cannot be opened
  explicit SerialFrameWriter(const std::string& device, int baud = 921600);

  /// Encodes `sample` and writes the whole frame, waiting in poll() while the device is full
  /// (up to kWriteTimeoutMs). Also reads any haptic frames waiting. False, with the device
  /// closed, when it is gone; false with it open when the write timed out.
  bool write_sample(const GloveSample& sample) noexcept;

  /// Writes bytes as they are, fully, like write_sample (for fault injection and relays).
  bool write_raw(std::span<const std::uint8_t> bytes) noexcept;

  /// Closes and opens the same device again (after it disappeared). False when it cannot be
  /// opened yet; last_error() says why.
  /// @throw SerialPort::RateRefused when the device now runs the line at another rate
  bool reopen();

  /// Whether the device is open.
  bool is_open() const noexcept { return port_.is_open(); }
  /// Why the last reopen() failed.
  const std::string& last_error() const noexcept { return last_error_; }

  /// Reads and decodes whatever the host has sent, without blocking; returns the number of
  /// haptic frames that arrived in this call. A hung-up device is closed.
  std::size_t pump_input() noexcept;
  /// Haptic frames received so far (reads pending input first).
  std::uint64_t haptic_frames_received() noexcept;
  /// The newest haptic command received, if any.
  const std::optional<HapticCommand>& last_haptic() const noexcept { return last_haptic_; }
  /// The decoder's counters for the host-to-glove direction.
  const DecoderCounters& input_counters() const noexcept { return decoder_.counters(); }

 private:
  std::string device_;
  int baud_;
  SerialPort port_;
  FrameDecoder decoder_;
  std::array<std::uint8_t, kMaxFrameBytes> frame_{};
  std::array<std::uint8_t, 1024> input_{};
  std::uint64_t haptic_frames_ = 0;
  std::optional<HapticCommand> last_haptic_;
  std::string last_error_;
};

}  // namespace sculpt::hal
