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
#include "sculpt/base/spsc_queue.hpp"

struct libusb_context;
struct libusb_device;
struct libusb_device_handle;
struct libusb_transfer;

namespace sculpt::hal {

/// Reads the glove through libusb's asynchronous API on a private context: a few IN transfers
/// stay submitted on the configured endpoint, and an event-handling thread runs their
/// callbacks, which feed the bytes to a FrameDecoder and queue the samples.
///
/// Hot-unplug: a transfer ending with LIBUSB_TRANSFER_NO_DEVICE (or a resubmit failing with
/// LIBUSB_ERROR_NO_DEVICE) makes the state kDisconnected and counts a disconnect; the event
/// thread then tries to reopen the device every 200 ms, at once when libusb reports its
/// arrival (hotplug, where the platform has it), and counts a reconnect when it succeeds.
/// On Linux libusb learns of arrivals only from udev's events, so where no udev daemon runs
/// (containers, an initramfs) its device list would never show the device again: every
/// fifth failed attempt therefore starts a fresh libusb context, which scans the bus anew.
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

  /// For libusb's hotplug callback only (its signature needs libusb.h, which this header
  /// keeps out): tells the event thread that a matching device arrived. `self` is the source.
  static void note_arrival(void* self) noexcept;

 private:
  static constexpr std::size_t kTransfers = 4;
  static constexpr std::size_t kTransferBytes = 512;

  /// Opens, claims and submits; returns 0 or a libusb error code, and on failure leaves the
  /// device closed. `why` names the failed step.
  int open_device(const char*& why) noexcept;
  void close_device() noexcept;
  void run() noexcept;
  void on_transfer(libusb_transfer* transfer) noexcept;
  void on_bytes(const std::uint8_t* data, std::size_t size) noexcept;
  void lost_device() noexcept;
  /// Replaces the libusb context by a new one (no device open, no transfer in flight).
  void refresh_context() noexcept;
  void register_hotplug() noexcept;
  static void transfer_callback(libusb_transfer* transfer);

  UsbConfig config_;
  base::SpscQueue<GloveSample> queue_;
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> arrived_{false};  // set by the hotplug callback
  bool device_lost_ = false;          // event thread only, like everything below
  unsigned failed_reopens_ = 0;
  libusb_context* context_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  int hotplug_handle_ = 0;
  bool hotplug_registered_ = false;
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
