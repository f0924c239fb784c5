#pragma once
// The interface every glove backend implements (serial, usb, lcm, socketcan, sim).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>

#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// Fault and traffic counters, written by the backend's I/O thread, read by anyone.
struct SourceCounters {
  std::uint64_t samples = 0;         ///< samples decoded and queued
  std::uint64_t crc_errors = 0;      ///< frames whose checksum failed
  std::uint64_t framing_errors = 0;  ///< garbage, truncated or malformed frames (bytes skipped to resync)
  std::uint64_t sequence_gaps = 0;   ///< samples missing by the device's sequence numbers
  std::uint64_t overflows = 0;       ///< samples dropped because the loop's queue was full
  std::uint64_t reconnects = 0;      ///< times the device came back after disappearing
  std::uint64_t disconnects = 0;     ///< times the device disappeared
  std::uint64_t error_frames = 0;    ///< CAN error frames
  std::uint64_t bus_off = 0;         ///< CAN bus-off events
};

/// The same counters as atomics, for the I/O thread to bump without locks.
struct AtomicSourceCounters {
  std::atomic<std::uint64_t> samples{0}, crc_errors{0}, framing_errors{0}, sequence_gaps{0}, overflows{0},
      reconnects{0}, disconnects{0}, error_frames{0}, bus_off{0};
  SourceCounters snapshot() const noexcept;
};

enum class SourceState : std::uint8_t { kStopped, kConnecting, kConnected, kDisconnected };

/// Set-up (start, stop) may allocate, block and throw with a clear message; poll() runs every
/// tick of the real-time loop: noexcept, no allocation, no lock shared with I/O.
class GloveSource {
 public:
  virtual ~GloveSource() = default;
  /// Opens the device and starts the I/O thread. Throws std::runtime_error naming the device
  /// and the reason when it cannot (backends that reconnect by themselves may instead start in
  /// kConnecting and keep trying).
  virtual void start() = 0;
  /// Stops the I/O thread and closes the device. Idempotent.
  virtual void stop() = 0;
  /// Moves the samples queued since the last call into `out`, oldest first; returns how many.
  virtual std::size_t poll(std::span<GloveSample> out) noexcept = 0;
  virtual SourceCounters counters() const noexcept = 0;
  virtual SourceState state() const noexcept = 0;
  virtual const char* name() const noexcept = 0;
};

}  // namespace sculpt::hal
