#include "usb_glove_source.hpp"

#include "sculpt/base/clock.hpp"

#include <libusb.h>
#include <time.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace sculpt::hal {
namespace {

constexpr std::int64_t kReopenIntervalNs = 200'000'000;
constexpr unsigned kReopensPerRescan = 5;  // a fresh context (a new bus scan) once a second
constexpr int kEventTimeoutUs = 50'000;    // how long stop() may wait for the event thread to notice

std::string ids(const UsbConfig& c) {
  char text[16];
  std::snprintf(text, sizeof text, "%04x:%04x", static_cast<unsigned>(c.vendor_id),
                static_cast<unsigned>(c.product_id));
  return text;
}

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

// libusb may call this from inside libusb_hotplug_register_callback or the event thread; it
// only raises a flag, since opening a device from inside a hotplug callback is not allowed.
int LIBUSB_CALL on_hotplug(libusb_context*, libusb_device*, libusb_hotplug_event, void* self) {
  UsbGloveSource::note_arrival(self);
  return 0;  // stay registered
}

}  // namespace

UsbGloveSource::UsbGloveSource(const UsbConfig& config, std::size_t queue_capacity)
    : config_(config), queue_(queue_capacity) {
  if (config.interface_number < 0)
    throw std::invalid_argument("glove.usb.interface_number: " + std::to_string(config.interface_number) +
                                " is negative");
  if ((config.endpoint & LIBUSB_ENDPOINT_IN) == 0)
    throw std::invalid_argument("glove.usb.endpoint: " + std::to_string(config.endpoint) +
                                " is not an IN endpoint (bit 7 clear)");
}

UsbGloveSource::~UsbGloveSource() { stop(); }

int UsbGloveSource::open_device(const char*& why) noexcept {
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
      close_device();
      return rc;
    }
  }
  why = "claim the interface";
  rc = libusb_claim_interface(handle_, config_.interface_number);
  if (rc != 0) {
    close_device();
    return rc;
  }
  decoder_.reset();
  why = "submit a transfer";
  for (std::size_t i = 0; i < kTransfers; ++i) {
    libusb_transfer* t = transfers_[i];
    if (config_.transfer == UsbConfig::Transfer::kInterrupt)
      libusb_fill_interrupt_transfer(t, handle_, config_.endpoint, buffers_[i].data(), static_cast<int>(kTransferBytes),
                                     &UsbGloveSource::transfer_callback, this, 0);
    else
      libusb_fill_bulk_transfer(t, handle_, config_.endpoint, buffers_[i].data(), static_cast<int>(kTransferBytes),
                                &UsbGloveSource::transfer_callback, this, 0);
    rc = libusb_submit_transfer(t);
    if (rc != 0) {
      device_lost_ = true;  // let the already submitted ones drain, then close
      return rc;
    }
    in_flight_[i] = true;
  }
  device_lost_ = false;
  return 0;
}

void UsbGloveSource::close_device() noexcept {
  if (handle_ == nullptr) return;
  libusb_release_interface(handle_, config_.interface_number);
  libusb_close(handle_);
  handle_ = nullptr;
}

void UsbGloveSource::start() {
  if (thread_.joinable()) return;
  const int rc_init = libusb_init(&context_);
  if (rc_init != 0) {
    context_ = nullptr;
    throw std::runtime_error("usb: cannot look for device " + ids(config_) + ": libusb_init failed (" +
                             std::string(libusb_strerror(rc_init)) + ")");
  }
  for (auto& t : transfers_) {
    t = libusb_alloc_transfer(0);
    if (t == nullptr) {
      stop();
      throw std::runtime_error("usb: " + ids(config_) + ": cannot allocate transfers");
    }
  }
  const char* why = "";
  const int rc = open_device(why);
  if (rc != 0) {
    const bool any_in_flight = in_flight_[0];
    stop_requested_.store(true);
    if (any_in_flight) {
      for (std::size_t i = 0; i < kTransfers; ++i)
        if (in_flight_[i]) libusb_cancel_transfer(transfers_[i]);
      while (in_flight_[0] || in_flight_[1] || in_flight_[2] || in_flight_[3]) libusb_handle_events(context_);
    }
    close_device();
    stop();
    if (rc == LIBUSB_ERROR_NOT_FOUND && std::string(why) == "find")
      throw std::runtime_error("usb: no device " + ids(config_) + " found");
    throw std::runtime_error("usb: " + ids(config_) + ": cannot " + why + " (" + libusb_strerror(rc) +
                             (rc == LIBUSB_ERROR_ACCESS ? "; check the udev rules" : "") + ")");
  }
  register_hotplug();
  stop_requested_.store(false, std::memory_order_relaxed);
  state_.store(SourceState::kConnected, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void UsbGloveSource::register_hotplug() noexcept {
  if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) return;
  hotplug_registered_ = libusb_hotplug_register_callback(
                            context_, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED, LIBUSB_HOTPLUG_NO_FLAGS, config_.vendor_id,
                            config_.product_id, LIBUSB_HOTPLUG_MATCH_ANY, &on_hotplug, this, &hotplug_handle_) == 0;
}

void UsbGloveSource::refresh_context() noexcept {
  // A submitted transfer keeps a reference to its device until it is freed or submitted
  // again (libusb 1.0.26), so the old context's transfers go with it: released after the old
  // context is gone, that reference would be released into freed memory.
  std::array<libusb_transfer*, kTransfers> fresh_transfers{};
  for (auto& t : fresh_transfers) {
    t = libusb_alloc_transfer(0);
    if (t == nullptr) {
      for (auto* f : fresh_transfers) libusb_free_transfer(f);  // null is a no-op
      return;                                                   // keep the old context; try again at the next rescan
    }
  }
  libusb_context* fresh = nullptr;
  if (libusb_init(&fresh) != 0) {
    for (auto* f : fresh_transfers) libusb_free_transfer(f);
    return;
  }
  if (hotplug_registered_) libusb_hotplug_deregister_callback(context_, hotplug_handle_);
  hotplug_registered_ = false;
  for (auto* t : transfers_) libusb_free_transfer(t);
  transfers_ = fresh_transfers;
  libusb_exit(context_);
  context_ = fresh;
  register_hotplug();
}

void UsbGloveSource::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (context_ != nullptr) {
    // The event thread cancelled and drained the transfers before it returned.
    if (hotplug_registered_) libusb_hotplug_deregister_callback(context_, hotplug_handle_);
    hotplug_registered_ = false;
    close_device();
  }
  for (auto& t : transfers_) {
    if (t != nullptr) libusb_free_transfer(t);
    t = nullptr;
  }
  if (context_ != nullptr) libusb_exit(context_);
  context_ = nullptr;
  state_.store(SourceState::kStopped, std::memory_order_release);
}

void UsbGloveSource::transfer_callback(libusb_transfer* transfer) {
  static_cast<UsbGloveSource*>(transfer->user_data)->on_transfer(transfer);
}

void UsbGloveSource::note_arrival(void* self) noexcept {
  static_cast<UsbGloveSource*>(self)->arrived_.store(true, std::memory_order_release);
}

void UsbGloveSource::lost_device() noexcept {
  if (device_lost_) return;
  device_lost_ = true;
  state_.store(SourceState::kDisconnected, std::memory_order_release);
  counters_.disconnects.fetch_add(1, std::memory_order_relaxed);
}

void UsbGloveSource::on_transfer(libusb_transfer* t) noexcept {
  std::size_t i = 0;
  while (i < kTransfers && transfers_[i] != t) ++i;
  if (i == kTransfers) return;
  in_flight_[i] = false;
  switch (t->status) {
    case LIBUSB_TRANSFER_COMPLETED: on_bytes(t->buffer, static_cast<std::size_t>(t->actual_length)); break;
    case LIBUSB_TRANSFER_NO_DEVICE: lost_device(); return;
    case LIBUSB_TRANSFER_CANCELLED: return;
    default:  // error, stall, overflow, timeout: the bytes are gone; the decoder resyncs
      counters_.framing_errors.fetch_add(1, std::memory_order_relaxed);
      break;
  }
  if (stop_requested_.load(std::memory_order_acquire) || device_lost_) return;
  const int rc = libusb_submit_transfer(t);
  if (rc == 0)
    in_flight_[i] = true;
  else
    lost_device();  // NO_DEVICE, or anything else that stops the stream: reopen
}

void UsbGloveSource::on_bytes(const std::uint8_t* data, std::size_t size) noexcept {
  decoder_.feed(std::span<const std::uint8_t>(data, size), [this](const DecodedFrame& frame) {
    if (frame.type != DecodedFrame::Type::kSample) return;  // haptic frames go the other way
    GloveSample s = frame.sample;
    s.receive_time_ns = base::monotonic_now_ns();
    sequences_.observe(s.hand, s.sequence);
    if (queue_.push(s))
      counters_.samples.fetch_add(1, std::memory_order_relaxed);
    else
      counters_.overflows.fetch_add(1, std::memory_order_relaxed);
  });
  const DecoderCounters& c = decoder_.counters();
  counters_.crc_errors.fetch_add(c.crc_errors - reported_.crc_errors, std::memory_order_relaxed);
  counters_.framing_errors.fetch_add(c.framing_errors - reported_.framing_errors, std::memory_order_relaxed);
  counters_.sequence_gaps.fetch_add(sequences_.gaps() - reported_gaps_, std::memory_order_relaxed);
  reported_ = c;
  reported_gaps_ = sequences_.gaps();
}

void UsbGloveSource::run() noexcept {
  const auto any_in_flight = [this] {
    for (const bool f : in_flight_)
      if (f) return true;
    return false;
  };
  std::int64_t next_attempt = 0;
  timeval tv{0, kEventTimeoutUs};
  while (!stop_requested_.load(std::memory_order_acquire)) {
    libusb_handle_events_timeout_completed(context_, &tv, nullptr);
    if (!device_lost_) continue;
    // Wait for every transfer to come back before closing the handle under them.
    if (any_in_flight()) continue;
    close_device();
    const std::int64_t now = base::monotonic_now_ns();
    if (!arrived_.exchange(false) && now < next_attempt) continue;
    next_attempt = now + kReopenIntervalNs;
    const char* why = "";
    if (open_device(why) != 0) {
      if (++failed_reopens_ % kReopensPerRescan == 0 && !any_in_flight()) refresh_context();
      continue;
    }
    failed_reopens_ = 0;
    // A reopened device restarts its counters; do not count that jump as lost samples.
    sequences_.reset();
    reported_gaps_ = 0;
    counters_.reconnects.fetch_add(1, std::memory_order_relaxed);
    state_.store(SourceState::kConnected, std::memory_order_release);
  }
  for (std::size_t i = 0; i < kTransfers; ++i)
    if (in_flight_[i]) libusb_cancel_transfer(transfers_[i]);
  while (any_in_flight()) libusb_handle_events_timeout_completed(context_, &tv, nullptr);
}

std::size_t UsbGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters UsbGloveSource::counters() const noexcept { return counters_.snapshot(); }

}  // namespace sculpt::hal
