#pragma once
// The glove as a USB device (libusb-1.0), speaking the frame protocol of
// docs/glove-protocol.md over an interrupt or bulk IN endpoint.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sequence_tracker.hpp"
#include "usb_device.hpp"
#include "sculpt/base/spsc_queue.hpp"

struct libusb_transfer;

namespace sculpt::hal {

/// Reads the glove through libusb's asynchronous API on a private context: a few IN transfers
/// stay submitted on the configured endpoint, and an event-handling thread runs their
/// callbacks, which feed the bytes to a FrameDecoder and queue the samples.
///
/// Hot-unplug: a transfer ending with LIBUSB_TRANSFER_NO_DEVICE (or a resubmit failing with
/// LIBUSB_ERROR_NO_DEVICE) makes the state kDisconnected and counts a disconnect; once every
/// transfer is back the event thread reopens the device as UsbDevice paces it (every 200 ms, a
/// fresh libusb context every fifth failure, since without udev libusb never sees it return)
/// and counts a reconnect when it succeeds.
class UsbGloveSource final : public GloveSource {
 public:
  /// @throw std::invalid_argument when interface_number is negative or endpoint is not IN.
  UsbGloveSource(const UsbConfig& config, std::size_t queue_capacity = 1024);
  ~UsbGloveSource() override;
  UsbGloveSource(const UsbGloveSource&) = delete;
  UsbGloveSource& operator=(const UsbGloveSource&) = delete;

  /// Opens the device, claims the interface (detaching a kernel driver), submits the
  /// transfers and starts the event thread. No-op while running.
  /// @throw std::runtime_error "usb: no device 1234:5678 found", or "usb: 1234:5678: ..."
  ///   naming the step that failed (open: permissions; claim: interface busy).
  void start() override;
  void stop() override;
  std::size_t poll(std::span<GloveSample> out) noexcept override;
  SourceCounters counters() const noexcept override;
  SourceState state() const noexcept override { return state_.load(std::memory_order_acquire); }
  const char* name() const noexcept override { return "usb"; }

 private:
  static constexpr std::size_t kTransfers = 4;
  static constexpr std::size_t kTransferBytes = 512;

  /// Opens, claims and submits; returns 0 or a libusb error code. `why` names the failed step.
  /// A failed submit leaves the device open until the transfers already submitted are back.
  int open_device(const char*& why) noexcept;
  void run() noexcept;
  void on_transfer(libusb_transfer* transfer) noexcept;
  void on_bytes(const std::uint8_t* data, std::size_t size) noexcept;
  void lost_device() noexcept;
  bool any_in_flight() const noexcept;
  /// Before a fresh libusb context replaces the old one: new transfers for the old ones, or
  /// false (keep the old context) while one is in flight or none can be allocated.
  bool renew_transfers() noexcept;
  static void transfer_callback(libusb_transfer* transfer);

  UsbConfig config_;
  base::SpscQueue<GloveSample> queue_;
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::atomic<bool> stop_requested_{false};
  bool device_lost_ = false;  // event thread only, like everything below
  UsbDevice device_;
  std::array<libusb_transfer*, kTransfers> transfers_{};
  std::array<bool, kTransfers> in_flight_{};
  std::array<std::array<std::uint8_t, kTransferBytes>, kTransfers> buffers_{};
  FrameDecoder decoder_;
  DecoderCounters reported_{};
  SequenceTracker sequences_;
  std::uint64_t reported_gaps_ = 0;
  std::thread thread_;
};

}  // namespace sculpt::hal
