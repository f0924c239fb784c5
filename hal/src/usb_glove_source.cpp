#include "usb_glove_source.hpp"

#include "sculpt/base/clock.hpp"

#include <libusb.h>
#include <time.h>

#include <stdexcept>
#include <string>

namespace sculpt::hal {
namespace {

constexpr int kEventTimeoutUs = 50'000;  // how long stop() may wait for the event thread to notice

}  // namespace

UsbGloveSource::UsbGloveSource(const UsbConfig& config, std::size_t queue_capacity)
    : config_(config), queue_(queue_capacity), device_(config, "usb") {
  if (config.interface_number < 0)
    throw std::invalid_argument("glove.usb.interface_number: " + std::to_string(config.interface_number) +
                                " is negative");
  if ((config.endpoint & LIBUSB_ENDPOINT_IN) == 0)
    throw std::invalid_argument("glove.usb.endpoint: " + std::to_string(config.endpoint) +
                                " is not an IN endpoint (bit 7 clear)");
}

UsbGloveSource::~UsbGloveSource() { stop(); }

int UsbGloveSource::open_device(const char*& why) noexcept {
  int rc = device_.open(why);
  if (rc != 0) return rc;
  decoder_.reset();
  why = "submit a transfer";
  for (std::size_t i = 0; i < kTransfers; ++i) {
    libusb_transfer* t = transfers_[i];
    if (config_.transfer == UsbConfig::Transfer::kInterrupt)
      libusb_fill_interrupt_transfer(t, device_.handle(), config_.endpoint, buffers_[i].data(),
                                     static_cast<int>(kTransferBytes), &UsbGloveSource::transfer_callback, this, 0);
    else
      libusb_fill_bulk_transfer(t, device_.handle(), config_.endpoint, buffers_[i].data(),
                                static_cast<int>(kTransferBytes), &UsbGloveSource::transfer_callback, this, 0);
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

bool UsbGloveSource::any_in_flight() const noexcept {
  for (const bool f : in_flight_)
    if (f) return true;
  return false;
}

void UsbGloveSource::start() {
  if (thread_.joinable()) return;
  device_.init();
  for (auto& t : transfers_) {
    t = libusb_alloc_transfer(0);
    if (t == nullptr) {
      stop();
      throw std::runtime_error("usb: " + device_.ids() + ": cannot allocate transfers");
    }
  }
  const char* why = "";
  const int rc = open_device(why);
  if (rc != 0) {
    stop_requested_.store(true);
    for (std::size_t i = 0; i < kTransfers; ++i)
      if (in_flight_[i]) libusb_cancel_transfer(transfers_[i]);
    while (any_in_flight()) libusb_handle_events(device_.context());
    stop();
    throw std::runtime_error(device_.open_error(rc, why));
  }
  stop_requested_.store(false, std::memory_order_relaxed);
  state_.store(SourceState::kConnected, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

bool UsbGloveSource::renew_transfers() noexcept {
  // A submitted transfer keeps a reference to its device until it is freed or submitted
  // again (libusb 1.0.26), so the old context's transfers go with it: released after the old
  // context is gone, that reference would be released into freed memory.
  if (any_in_flight()) return false;
  std::array<libusb_transfer*, kTransfers> fresh{};
  for (auto& t : fresh) {
    t = libusb_alloc_transfer(0);
    if (t == nullptr) {
      for (auto* f : fresh) libusb_free_transfer(f);  // null is a no-op
      return false;
    }
  }
  for (auto* t : transfers_) libusb_free_transfer(t);
  transfers_ = fresh;
  return true;
}

void UsbGloveSource::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  // The event thread cancelled and drained the transfers before it returned.
  device_.close();
  for (auto& t : transfers_) {
    if (t != nullptr) libusb_free_transfer(t);
    t = nullptr;
  }
  device_.exit();
  state_.store(SourceState::kStopped, std::memory_order_release);
}

void UsbGloveSource::transfer_callback(libusb_transfer* transfer) {
  static_cast<UsbGloveSource*>(transfer->user_data)->on_transfer(transfer);
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
  timeval tv{0, kEventTimeoutUs};
  while (!stop_requested_.load(std::memory_order_acquire)) {
    libusb_handle_events_timeout_completed(device_.context(), &tv, nullptr);
    if (!device_lost_) continue;
    // Wait for every transfer to come back before closing the handle under them.
    if (any_in_flight()) continue;
    device_.close();
    const auto open = [this] {
      const char* why = "";
      return open_device(why);
    };
    if (!device_.try_reopen(base::monotonic_now_ns(), open, [this] { return renew_transfers(); })) continue;
    // A reopened device restarts its counters; do not count that jump as lost samples.
    sequences_.reset();
    reported_gaps_ = 0;
    counters_.reconnects.fetch_add(1, std::memory_order_relaxed);
    state_.store(SourceState::kConnected, std::memory_order_release);
  }
  for (std::size_t i = 0; i < kTransfers; ++i)
    if (in_flight_[i]) libusb_cancel_transfer(transfers_[i]);
  while (any_in_flight()) libusb_handle_events_timeout_completed(device_.context(), &tv, nullptr);
}

std::size_t UsbGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters UsbGloveSource::counters() const noexcept { return counters_.snapshot(); }

}  // namespace sculpt::hal
