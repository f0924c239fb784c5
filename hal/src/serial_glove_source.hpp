#pragma once
// The glove on a serial line (USB CDC-ACM, FTDI, or a pseudo-terminal in tests), speaking the
// frame protocol of docs/glove-protocol.md.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sequence_tracker.hpp"
#include "sculpt/hal/serial_port.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// Reads glove frames from a serial device on its own I/O thread and queues the samples for
/// the loop. Survives the device disappearing: it counts a disconnect, closes, and reopens the
/// same path every reconnect_interval_ms until it is back (a reconnect). Haptic frames that
/// arrive on this line are ignored.
class SerialGloveSource final : public GloveSource {
 public:
  /// Validates the configuration and allocates the queue. Opens nothing yet.
  /// @throw std::invalid_argument naming the field: empty device, non-standard baud,
  ///        reconnect_interval_ms not positive and finite, queue_capacity 0
  SerialGloveSource(const SerialConfig& config, std::size_t queue_capacity);
  ~SerialGloveSource() override;
  SerialGloveSource(const SerialGloveSource&) = delete;
  SerialGloveSource& operator=(const SerialGloveSource&) = delete;

  /// Tries to open the device once, then starts the I/O thread, which keeps trying if that
  /// failed: the state is kConnected or kConnecting. A glove plugged in later is picked up.
  /// @throw std::runtime_error when already started, when the path exists but is not a
  ///        terminal, or when the thread cannot be created; SerialPort::RateRefused when the
  ///        device runs the line at another rate than config.baud; SerialPort::InUse when
  ///        another reader holds the device's lock (this source takes it while connected)
  void start() override;
  /// Stops the I/O thread (promptly: it is woken, not waited out) and closes the device.
  void stop() override;
  /// Moves queued samples into `out`, oldest first. Real-time safe; one consumer thread.
  std::size_t poll(std::span<GloveSample> out) noexcept override;
  SourceCounters counters() const noexcept override;
  SourceState state() const noexcept override;
  const char* name() const noexcept override { return "serial"; }

  /// Why the device could not be opened the last time it was tried (empty once open).
  /// Takes a lock the I/O thread holds briefly: not for the real-time loop.
  std::string last_error() const;

 private:
  void run() noexcept;
  bool try_connect() noexcept;
  /// try_connect's attempt, letting SerialPort's exceptions out (start() stops on a refused rate).
  bool connect();
  void disconnect() noexcept;
  void handle_bytes(std::span<const std::uint8_t> bytes) noexcept;

  SerialConfig config_;
  base::SpscQueue<GloveSample> queue_;
  // Owned by the I/O thread while it runs (by start() before it does).
  SerialPort port_;
  FrameDecoder decoder_;
  SequenceTracker tracker_;
  std::array<std::uint8_t, 4096> read_buffer_{};
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::thread thread_;
  std::atomic<bool> stop_requested_{false};
  int wake_fd_ = -1;  // eventfd: stop() writes it so the I/O thread's poll() returns at once
  mutable std::mutex error_mutex_;
  std::string last_error_;
  bool ever_connected_ = false;  // I/O thread only: tells a reconnect from the first connect
};

}  // namespace sculpt::hal
