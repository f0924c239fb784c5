#pragma once
// Haptic commands to a USB glove (libusb-1.0) as haptic frames of docs/glove-protocol.md,
// written to its bulk or interrupt OUT endpoint.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "delivery_counts.hpp"
#include "usb_device.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// send() only queues; the sink's own thread wakes every millisecond (kPeriodNs), takes what
/// is queued, keeps the newest command of each hand (older ones count as superseded: a force
/// is worthless once a newer one exists, so at most one frame per hand per millisecond goes
/// out) and writes it with a synchronous libusb transfer of at most kWriteTimeoutMs. A frame
/// not taken by then is dropped, never sent late; one cut short is followed by a 0x00, so the
/// glove's decoder drops the cut frame, not the next one.
///
/// What it promises the hand, whatever the loop sends:
/// - bounded: a finger's force magnitude above `max_force` is scaled down to it (direction
///   kept), and a finger with a non-finite component is sent as zero force and not in
///   contact (the glove would reject the whole frame otherwise); such commands count in
///   clamped();
/// - released on silence: when a hand's last frame carried force (or contact) and no command
///   for it has come for kReleaseAfterNs, the sink writes a release (no contact, zero force,
///   the last tick) itself, counted in releases(); stop() releases every hand it left pressed.
///
/// It claims the interface given (the OUT endpoint's), on a libusb context of its own: USB
/// lets one program claim an interface once, so a glove whose samples the USB source reads
/// must offer its OUT endpoint on an interface of its own. Unplugged (a transfer ends with
/// LIBUSB_ERROR_NO_DEVICE) it counts a disconnect, drops commands meanwhile, and reopens as
/// UsbDevice paces it (every 200 ms, with a fresh libusb context every fifth failure, since
/// without udev libusb never sees the device return); success counts a reconnect.
class UsbHapticSink final : public HapticSink {
 public:
  static constexpr std::int64_t kPeriodNs = 1'000'000;
  static constexpr int kWriteTimeoutMs = 50;
  static constexpr std::int64_t kReleaseAfterNs = 50'000'000;

  /// @throw std::invalid_argument when interface_number is negative, out_endpoint is not an
  ///   OUT endpoint (bit 7 set, or endpoint 0), max_force is not finite and positive, or
  ///   queue_capacity is 0.
  UsbHapticSink(const UsbConfig& config, float max_force, std::size_t queue_capacity = 256);
  ~UsbHapticSink() override;
  UsbHapticSink(const UsbHapticSink&) = delete;
  UsbHapticSink& operator=(const UsbHapticSink&) = delete;

  /// Opens the device, claims the interface and starts the writer thread. No-op while running.
  /// @throw std::runtime_error "usb haptic sink: no device 1234:5678 found", or
  ///   "usb haptic sink: 1234:5678: cannot ..." naming the step that failed.
  void start() override;
  /// Writes what is queued and the releases owed, then stops and closes. Idempotent.
  void stop() override;
  /// Queues the command. False, and counted as dropped, when the queue is full or the hand is
  /// out of range. Real-time safe (no allocation, lock or system call); one producer thread.
  bool send(const HapticCommand& command) noexcept override;
  /// Commands not delivered: queue full, hand out of range, device absent, write failed.
  std::uint64_t dropped() const noexcept override { return dropped_.load(std::memory_order_relaxed); }
  /// Commands written to the endpoint in full (releases of the sink's own not included).
  std::uint64_t delivered() const noexcept override { return written_.total(); }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override { return written_.in_contact(hand); }
  std::uint64_t superseded() const noexcept override { return superseded_.load(std::memory_order_relaxed); }
  const char* name() const noexcept override { return "usb"; }

  /// Commands in which a force was scaled down to max_force or a non-finite one zeroed.
  std::uint64_t clamped() const noexcept { return clamped_.load(std::memory_order_relaxed); }
  /// Releases the sink wrote itself (silence, stop).
  std::uint64_t releases() const noexcept { return releases_.load(std::memory_order_relaxed); }
  std::uint64_t disconnects() const noexcept { return disconnects_.load(std::memory_order_relaxed); }
  std::uint64_t reconnects() const noexcept { return reconnects_.load(std::memory_order_relaxed); }
  /// Whether the device is open right now.
  bool connected() const noexcept { return connected_.load(std::memory_order_acquire); }

  /// The command as the sink sends it: magnitudes scaled down to `max_force`, non-finite
  /// fingers zeroed and out of contact. Returns whether anything changed.
  static bool bound(HapticCommand& command, float max_force) noexcept;

 private:
  void run() noexcept;
  /// Takes the queue: the newest command of each hand into newest_, older ones superseded.
  void take_queue() noexcept;
  /// Writes newest_ and the releases due at `now_ns` (any release owed when `now_ns` < 0).
  void write_due(std::int64_t now_ns) noexcept;
  /// Encodes and writes one frame stamped `stamp_ns` (its device_time_us); false when it was
  /// not written in full.
  bool write(const HapticCommand& command, std::int64_t stamp_ns) noexcept;
  void lost_device() noexcept;

  UsbConfig config_;
  float max_force_;
  base::SpscQueue<HapticCommand> queue_;
  UsbDevice device_;  // writer thread only once started, like everything down to thread_
  /// One delimiter byte, then the frame: the delimiter goes out only after a cut frame.
  std::array<std::uint8_t, 1 + kMaxFrameBytes> frame_{};
  bool cut_frame_ = false;
  std::uint32_t sequence_ = 0;
  std::array<HapticCommand, kHands> newest_{};
  std::array<bool, kHands> have_{};
  /// Per hand: whether the glove may still be pressing (the last frame carried force or
  /// contact, or its fate is unknown), the last command's tick and its frame's stamp (the
  /// silence is timed from the stamp the glove sees, so a release is never stamped early).
  std::array<bool, kHands> pressing_{};
  std::array<std::uint32_t, kHands> last_tick_{};
  std::array<std::int64_t, kHands> last_command_ns_{};
  std::atomic<std::uint64_t> dropped_{0}, superseded_{0}, clamped_{0}, releases_{0};
  DeliveryCounts written_;
  std::atomic<std::uint64_t> disconnects_{0}, reconnects_{0};
  std::atomic<bool> connected_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
};

}  // namespace sculpt::hal
