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
#include "delivery_counts.hpp"
#include "sculpt/hal/serial_port.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// Queues commands from the loop and writes them as frames on its own I/O thread, through its
/// own descriptor on the device (the source reads on another one; this one never reads).
/// Frame sequence numbers count up from 0 per start(); device_time_us is the host's
/// CLOCK_MONOTONIC. Reconnects like SerialGloveSource. Commands that cannot be delivered
/// (device absent, or not draining for kWriteTimeoutMs) are discarded and counted in
/// dropped(): stale forces must never reach the hand late.
///
/// A serial line may be slower than the loop (a command is about 87 bytes, so one hand at
/// 1 kHz needs about 87 kB/s against about 92 kB/s at 921,600 baud; two hands do not fit).
/// Each time the writer gets to the queue it therefore sends only the newest command of each
/// hand and counts the older ones as superseded(): the line runs as fast as it can with the
/// newest force, and never drains a backlog of old ones. Nor may the driver: a UART driver
/// buffers about 4 KB (45 ms at 921,600 baud) behind which every new frame would wait, so a
/// frame is written only while at most kMaxBacklogBytes are still unsent; until then the newest
/// command of each hand is held, and a newer one supersedes it. A command therefore reaches the
/// wire at most about two frame times after the writer takes it.
class SerialHapticSink final : public HapticSink {
 public:
  /// How long one frame may wait for room on the device before it is dropped.
  static constexpr int kWriteTimeoutMs = 50;
  /// The most unsent bytes a new frame may queue behind: one haptic frame on the wire (its
  /// body, COBS's overhead byte per 254 and the delimiter).
  static constexpr std::size_t kMaxBacklogBytes = kHapticBodyBytes + kHapticBodyBytes / 254 + 2;
  /// Bytes written to `fd` and not yet on the wire. SerialPort::output_pending (TIOCOUTQ) by
  /// default; tests of a pty, where that is always 0, give what the reader has not read.
  using BacklogProbe = std::size_t (*)(int fd) noexcept;

  /// Validates the configuration and allocates the queue. Opens nothing yet.
  /// @throw std::invalid_argument naming the field (as SerialGloveSource)
  SerialHapticSink(const SerialConfig& config, std::size_t queue_capacity,
                   BacklogProbe backlog = &SerialPort::output_pending);
  ~SerialHapticSink() override;
  SerialHapticSink(const SerialHapticSink&) = delete;
  SerialHapticSink& operator=(const SerialHapticSink&) = delete;

  /// Tries to open the device once, then starts the writer thread, which keeps trying.
  /// @throw std::runtime_error when already started or the path is not a character device;
  ///   SerialPort::RateRefused when the device runs the line at another rate than config.baud
  void start() override;
  /// Stops the writer thread and closes the device. Idempotent.
  void stop() override;
  /// Queues the command and wakes the writer (a non-blocking eventfd write). False, and
  /// counted, when the queue is full. Real-time safe; one producer thread.
  bool send(const HapticCommand& command) noexcept override;
  /// Commands not delivered: queue full, device absent, or write timed out.
  std::uint64_t dropped() const noexcept override;
  std::uint64_t delivered() const noexcept override { return frames_written(); }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override { return written_.in_contact(hand); }
  std::uint64_t superseded() const noexcept override { return superseded_.load(std::memory_order_relaxed); }
  const char* name() const noexcept override { return "serial"; }

  /// Frames written to the device completely.
  std::uint64_t frames_written() const noexcept;
  /// Whether the device is open right now.
  bool connected() const noexcept;

 private:
  void run() noexcept;
  bool try_connect() noexcept;
  /// try_connect's attempt, letting SerialPort's exceptions out (start() stops on a refused rate).
  bool connect();
  /// Sends the newest command of each hand; true when one is held back for the backlog.
  bool drain_queue() noexcept;
  /// Writes the whole frame, or gives up after kWriteTimeoutMs; `sent` counts bytes written.
  bool write_frame(std::span<const std::uint8_t> frame, std::size_t& sent) noexcept;
  void deliver(const HapticCommand& command) noexcept;

  SerialConfig config_;
  base::SpscQueue<HapticCommand> queue_;
  SerialPort port_;
  /// One delimiter byte, then the frame: the delimiter is sent only after a frame was cut
  /// short by a write timeout, so the glove's decoder drops the cut frame, not the next one.
  std::array<std::uint8_t, 1 + kMaxFrameBytes> frame_{};
  bool cut_frame_on_line_ = false;
  BacklogProbe backlog_;
  /// The newest command of each hand not yet written (waiting for the driver's backlog).
  std::array<HapticCommand, kHands> held_{};
  std::array<bool, kHands> holding_{};
  std::uint32_t sequence_ = 0;
  std::atomic<std::uint64_t> dropped_{0};
  DeliveryCounts written_;
  std::atomic<std::uint64_t> superseded_{0};
  std::atomic<bool> connected_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
  int wake_fd_ = -1;
};

}  // namespace sculpt::hal
