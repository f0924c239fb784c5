#pragma once
// Haptic commands to the glove over its serial line, as haptic frames (docs/glove-protocol.md).

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "sculpt/hal/serial_port.hpp"
#include "sculpt/hal/spsc_queue.hpp"

namespace sculpt::hal {

/// Queues commands from the loop and writes them as frames on its own I/O thread, through its
/// own descriptor on the device (the source reads on another one; this one never reads).
/// Frame sequence numbers count up from 0 per start(); device_time_us is the host's
/// CLOCK_MONOTONIC. Reconnects like SerialGloveSource. Commands that cannot be delivered
/// (device absent, or not draining for kWriteTimeoutMs) are discarded and counted in
/// dropped(): stale forces must never reach the hand late.
class SerialHapticSink final : public HapticSink {
 public:
  /// How long one frame may wait for room on the device before it is dropped.
  static constexpr int kWriteTimeoutMs = 50;

  /// Validates the configuration and allocates the queue. Opens nothing yet.
  /// @throw std::invalid_argument naming the field (as SerialGloveSource)
  SerialHapticSink(const SerialConfig& config, std::size_t queue_capacity);
  ~SerialHapticSink() override;
  SerialHapticSink(const SerialHapticSink&) = delete;
  SerialHapticSink& operator=(const SerialHapticSink&) = delete;

  /// Tries to open the device once, then starts the writer thread, which keeps trying.
  /// @throw std::runtime_error when already started or the path is not a character device
  void start() override;
  /// Stops the writer thread and closes the device. Idempotent.
  void stop() override;
  /// Queues the command and wakes the writer (a non-blocking eventfd write). False, and
  /// counted, when the queue is full. Real-time safe; one producer thread.
  bool send(const HapticCommand& command) noexcept override;
  /// Commands not delivered: queue full, device absent, or write timed out.
  std::uint64_t dropped() const noexcept override;
  const char* name() const noexcept override { return "serial"; }

  /// Frames written to the device completely.
  std::uint64_t frames_written() const noexcept;
  /// Whether the device is open right now.
  bool connected() const noexcept;

 private:
  void run() noexcept;
  bool try_connect() noexcept;
  void drain_queue() noexcept;
  bool write_frame(std::span<const std::uint8_t> frame) noexcept;

  SerialConfig config_;
  SpscQueue<HapticCommand> queue_;
  SerialPort port_;
  std::array<std::uint8_t, kMaxFrameBytes> frame_{};
  std::uint32_t sequence_ = 0;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<bool> connected_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
  int wake_fd_ = -1;
};

}  // namespace sculpt::hal
