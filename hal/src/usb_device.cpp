#include "usb_device.hpp"

#include <libusb.h>

#include <cstdio>
#include <stdexcept>
#include <utility>

namespace sculpt::hal {
namespace {

// Finds the first device with the configured ids. Returns LIBUSB_ERROR_NOT_FOUND if none.
int find_device(libusb_context* ctx, const UsbConfig& c, libusb_device** found) noexcept {
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  if (n < 0) return static_cast<int>(n);
  int result = LIBUSB_ERROR_NOT_FOUND;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    if (d.idVendor == c.vendor_id && d.idProduct == c.product_id) {
      *found = libusb_ref_device(list[i]);
      result = 0;
      break;
    }
  }
  libusb_free_device_list(list, 1);
  return result;
}

// libusb may call this from inside libusb_hotplug_register_callback or while handling events;
// it only raises a flag, since opening a device from inside a hotplug callback is not allowed.
int LIBUSB_CALL on_hotplug(libusb_context*, libusb_device*, libusb_hotplug_event, void* self) {
  UsbDevice::note_arrival(self);
  return 0;  // stay registered
}

}  // namespace

UsbDevice::UsbDevice(const UsbConfig& config, std::string who) : config_(config), who_(std::move(who)) {}

UsbDevice::~UsbDevice() { exit(); }

std::string UsbDevice::ids() const {
  char text[16];
  std::snprintf(text, sizeof text, "%04x:%04x", static_cast<unsigned>(config_.vendor_id),
                static_cast<unsigned>(config_.product_id));
  return text;
}

void UsbDevice::init() {
  if (context_ != nullptr) return;
  const int rc = libusb_init(&context_);
  if (rc != 0) {
    context_ = nullptr;
    throw std::runtime_error(who_ + ": cannot look for device " + ids() + ": libusb_init failed (" +
                             libusb_strerror(rc) + ")");
  }
  failed_reopens_ = 0;
  next_attempt_ns_ = 0;
  register_hotplug();
}

void UsbDevice::exit() noexcept {
  close();
  if (context_ == nullptr) return;
  deregister_hotplug();
  libusb_exit(context_);
  context_ = nullptr;
}

int UsbDevice::open(const char*& why) noexcept {
  libusb_device* device = nullptr;
  why = "find";
  int rc = find_device(context_, config_, &device);
  if (rc != 0) return rc;
  why = "open";
  rc = libusb_open(device, &handle_);
  libusb_unref_device(device);
  if (rc != 0) {
    handle_ = nullptr;
    return rc;
  }
  why = "detach the kernel driver";
  if (libusb_kernel_driver_active(handle_, config_.interface_number) == 1) {
    rc = libusb_detach_kernel_driver(handle_, config_.interface_number);
    if (rc != 0 && rc != LIBUSB_ERROR_NOT_FOUND) {
      close();
      return rc;
    }
  }
  why = "claim the interface";
  rc = libusb_claim_interface(handle_, config_.interface_number);
  if (rc != 0) {
    close();
    return rc;
  }
  return 0;
}

void UsbDevice::close() noexcept {
  if (handle_ == nullptr) return;
  libusb_release_interface(handle_, config_.interface_number);
  libusb_close(handle_);
  handle_ = nullptr;
}

std::string UsbDevice::open_error(int rc, const char* why) const {
  if (rc == LIBUSB_ERROR_NOT_FOUND && std::string(why) == "find") return who_ + ": no device " + ids() + " found";
  return who_ + ": " + ids() + ": cannot " + why + " (" + libusb_strerror(rc) +
         (rc == LIBUSB_ERROR_ACCESS ? "; check the udev rules" : "") +
         (rc == LIBUSB_ERROR_BUSY ? "; is another program, or the glove source, holding interface " +
                                        std::to_string(config_.interface_number) + "?"
                                  : "") +
         ")";
}

void UsbDevice::poll_events() noexcept {
  timeval zero{0, 0};
  libusb_handle_events_timeout_completed(context_, &zero, nullptr);
}

void UsbDevice::note_arrival(void* self) noexcept {
  static_cast<UsbDevice*>(self)->arrived_.store(true, std::memory_order_release);
}

bool UsbDevice::take_arrival() noexcept { return arrived_.exchange(false, std::memory_order_acq_rel); }

libusb_context* UsbDevice::fresh_context() noexcept {
  libusb_context* fresh = nullptr;
  return libusb_init(&fresh) == 0 ? fresh : nullptr;
}

void UsbDevice::discard_context(libusb_context* context) noexcept { libusb_exit(context); }

void UsbDevice::replace_context(libusb_context* fresh) noexcept {
  close();
  deregister_hotplug();
  libusb_exit(context_);
  context_ = fresh;
  register_hotplug();
}

void UsbDevice::register_hotplug() noexcept {
  if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) return;
  hotplug_registered_ = libusb_hotplug_register_callback(
                            context_, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, LIBUSB_HOTPLUG_NO_FLAGS, config_.vendor_id,
                            config_.product_id, LIBUSB_HOTPLUG_MATCH_ANY, &on_hotplug, this, &hotplug_handle_) == 0;
}

void UsbDevice::deregister_hotplug() noexcept {
  if (hotplug_registered_) libusb_hotplug_deregister_callback(context_, hotplug_handle_);
  hotplug_registered_ = false;
}

}  // namespace sculpt::hal
