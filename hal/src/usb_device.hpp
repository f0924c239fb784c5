#pragma once
// One interface of a USB glove opened through libusb on a context of its own: finding the
// device by its ids, opening it, claiming the interface, and coming back after an unplug.
// Shared by the USB glove source and the USB haptic sink.

#include <atomic>
#include <cstdint>
#include <string>

#include "sculpt/hal/backend_config.hpp"

struct libusb_context;
struct libusb_device_handle;

namespace sculpt::hal {

/// Owns a libusb context and, while open, a handle with one claimed interface. Used by one
/// I/O thread at a time (set-up, then that thread); nothing here allocates after init().
///
/// Reopening (try_reopen) is paced to every 200 ms, or at once when libusb's hotplug reports
/// the device's arrival. On Linux libusb learns of arrivals only from udev's events, so where
/// no udev daemon runs (containers, an initramfs) its device list would never show the device
/// again: every fifth failed attempt therefore starts a fresh libusb context, which scans the
/// bus anew.
class UsbDevice {
 public:
  /// `who` starts every message ("usb", "usb haptic sink").
  UsbDevice(const UsbConfig& config, std::string who);
  ~UsbDevice();
  UsbDevice(const UsbDevice&) = delete;
  UsbDevice& operator=(const UsbDevice&) = delete;

  /// Creates the context and registers for arrivals where libusb can. No-op when it exists.
  /// @throw std::runtime_error "<who>: cannot look for device 1234:5678: libusb_init failed (...)"
  void init();
  /// Closes the device and ends the context. Idempotent.
  void exit() noexcept;

  /// Finds, opens, detaches a kernel driver from and claims the interface. Returns 0 or a
  /// libusb error code, leaving the device closed; `why` then names the failed step.
  int open(const char*& why) noexcept;
  void close() noexcept;
  bool is_open() const noexcept { return handle_ != nullptr; }

  /// The set-up error for a failed open(): "<who>: no device 1234:5678 found", or
  /// "<who>: 1234:5678: cannot <why> (<libusb's words>)".
  std::string open_error(int rc, const char* why) const;
  /// "1234:5678".
  std::string ids() const;

  /// While the device is lost and closed: reopens it if an attempt is due (see the class
  /// comment) and returns true when it is open again. `open` does the caller's whole opening
  /// (this class's open() and whatever the caller adds) and returns 0 or an error; `renew` runs
  /// before a fresh context replaces the old one, and must return false (vetoing the
  /// replacement) if anything of the caller's still refers to the old context, or release it.
  template <typename Open, typename Renew>
  bool try_reopen(std::int64_t now_ns, Open&& open, Renew&& renew) noexcept;

  /// Runs libusb's pending events (hotplug callbacks) without waiting.
  void poll_events() noexcept;

  libusb_context* context() const noexcept { return context_; }
  libusb_device_handle* handle() const noexcept { return handle_; }
  const UsbConfig& config() const noexcept { return config_; }

  /// For libusb's hotplug callback only (its signature needs libusb.h, which this header keeps
  /// out): notes that a matching device arrived. `self` is the UsbDevice.
  static void note_arrival(void* self) noexcept;

 private:
  static constexpr std::int64_t kReopenIntervalNs = 200'000'000;
  static constexpr unsigned kReopensPerRescan = 5;  // a fresh context (a new bus scan) once a second

  bool take_arrival() noexcept;
  /// A new context, or nullptr.
  static libusb_context* fresh_context() noexcept;
  /// Replaces the (closed) device's context by `fresh`.
  void replace_context(libusb_context* fresh) noexcept;
  static void discard_context(libusb_context* context) noexcept;
  void register_hotplug() noexcept;
  void deregister_hotplug() noexcept;

  UsbConfig config_;
  std::string who_;
  libusb_context* context_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  int hotplug_handle_ = 0;
  bool hotplug_registered_ = false;
  std::atomic<bool> arrived_{false};  // set by the hotplug callback
  std::int64_t next_attempt_ns_ = 0;
  unsigned failed_reopens_ = 0;
};

template <typename Open, typename Renew>
bool UsbDevice::try_reopen(std::int64_t now_ns, Open&& open, Renew&& renew) noexcept {
  if (!take_arrival() && now_ns < next_attempt_ns_) return false;
  next_attempt_ns_ = now_ns + kReopenIntervalNs;
  if (open() == 0) {
    failed_reopens_ = 0;
    return true;
  }
  if (++failed_reopens_ % kReopensPerRescan != 0) return false;
  libusb_context* fresh = fresh_context();
  if (fresh == nullptr) return false;  // keep the old context; try again at the next rescan
  if (!renew()) {
    discard_context(fresh);
    return false;
  }
  replace_context(fresh);
  return false;
}

}  // namespace sculpt::hal
