#include "usb_haptic_sink.hpp"

#include "sculpt/base/clock.hpp"

#include <libusb.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>

namespace sculpt::hal {
namespace {

const UsbConfig& checked(const UsbConfig& config, float max_force, std::size_t queue_capacity) {
  if (config.interface_number < 0)
    throw std::invalid_argument("haptic.usb.interface_number: " + std::to_string(config.interface_number) +
                                " is negative");
  if ((config.out_endpoint & LIBUSB_ENDPOINT_IN) != 0 || (config.out_endpoint & LIBUSB_ENDPOINT_ADDRESS_MASK) == 0)
    throw std::invalid_argument("haptic.usb.out_endpoint: " + std::to_string(config.out_endpoint) +
                                " is not an OUT endpoint (0x01 .. 0x0F)");
  if (!std::isfinite(max_force) || max_force <= 0.0f)
    throw std::invalid_argument("haptic.max_force: " + std::to_string(max_force) + " is not a positive force");
  if (queue_capacity == 0) throw std::invalid_argument("haptic.queue_capacity: must be > 0");
  return config;
}

bool carries_force(const HapticCommand& c) noexcept {
  if (c.active_mask != 0) return true;
  for (const Point3f& f : c.force)
    for (const float component : f)
      if (component != 0.0f) return true;
  return false;
}

}  // namespace

UsbHapticSink::UsbHapticSink(const UsbConfig& config, float max_force, std::size_t queue_capacity)
    : config_(checked(config, max_force, queue_capacity)),
      max_force_(max_force),
      queue_(queue_capacity),
      device_(config, "usb haptic sink") {}

UsbHapticSink::~UsbHapticSink() { stop(); }

bool UsbHapticSink::bound(HapticCommand& command, float max_force) noexcept {
  bool changed = false;
  for (std::size_t f = 0; f < kFingers; ++f) {
    Point3f& v = command.force[f];
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      v = Point3f{};
      command.active_mask = static_cast<std::uint8_t>(command.active_mask & ~(1u << f));
      changed = true;
      continue;
    }
    // In double, so that the square cannot overflow and the scaled force is not above the bound.
    const double x = v[0], y = v[1], z = v[2];
    const double norm = std::sqrt(x * x + y * y + z * z);
    if (norm <= max_force) continue;
    const double scale = max_force / norm;
    v = Point3f{static_cast<float>(x * scale), static_cast<float>(y * scale), static_cast<float>(z * scale)};
    changed = true;
  }
  return changed;
}

void UsbHapticSink::start() {
  if (thread_.joinable()) return;
  device_.init();
  const char* why = "";
  const int rc = device_.open(why);
  if (rc != 0) {
    device_.exit();
    throw std::runtime_error(device_.open_error(rc, why));
  }
  sequence_ = 0;
  cut_frame_ = false;
  have_ = {};
  pressing_ = {};
  stop_requested_.store(false, std::memory_order_relaxed);
  connected_.store(true, std::memory_order_release);
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error& e) {
    device_.exit();
    connected_.store(false, std::memory_order_release);
    throw std::runtime_error("usb haptic sink: " + device_.ids() + ": cannot start the I/O thread: " + e.what());
  }
}

void UsbHapticSink::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  device_.exit();
  connected_.store(false, std::memory_order_release);
}

bool UsbHapticSink::send(const HapticCommand& command) noexcept {
  if (command.hand < kHands && queue_.push(command)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void UsbHapticSink::lost_device() noexcept {
  device_.close();
  cut_frame_ = false;  // a new connection starts clean
  connected_.store(false, std::memory_order_release);
  disconnects_.fetch_add(1, std::memory_order_relaxed);
}

bool UsbHapticSink::write(const HapticCommand& command, std::int64_t stamp_ns) noexcept {
  if (!device_.is_open()) return false;
  const std::size_t n = encode_haptic_frame(command, sequence_++, static_cast<std::uint64_t>(stamp_ns / 1000),
                                            std::span<std::uint8_t>(frame_).subspan(1));
  const std::size_t begin = cut_frame_ ? 0 : 1;  // frame_[0] is a 0x00 delimiter
  const int length = static_cast<int>(1 + n - begin);
  int transferred = 0;
  const int rc = config_.transfer == UsbConfig::Transfer::kInterrupt
                     ? libusb_interrupt_transfer(device_.handle(), config_.out_endpoint, frame_.data() + begin, length,
                                                 &transferred, kWriteTimeoutMs)
                     : libusb_bulk_transfer(device_.handle(), config_.out_endpoint, frame_.data() + begin, length,
                                            &transferred, kWriteTimeoutMs);
  if (rc == 0 && transferred == length) {
    cut_frame_ = false;
    return true;
  }
  if (rc == LIBUSB_ERROR_NO_DEVICE) {
    lost_device();
    return false;
  }
  if (rc == LIBUSB_ERROR_PIPE) libusb_clear_halt(device_.handle(), config_.out_endpoint);
  cut_frame_ = cut_frame_ || transferred > 0;
  return false;
}

void UsbHapticSink::take_queue() noexcept {
  HapticCommand c;
  while (queue_.pop(c)) {
    if (have_[c.hand]) superseded_.fetch_add(1, std::memory_order_relaxed);
    newest_[c.hand] = c;
    have_[c.hand] = true;
  }
}

void UsbHapticSink::write_due(std::int64_t now_ns) noexcept {
  for (std::size_t h = 0; h < kHands; ++h) {
    if (have_[h]) {
      have_[h] = false;
      HapticCommand& c = newest_[h];
      if (bound(c, max_force_)) clamped_.fetch_add(1, std::memory_order_relaxed);
      last_tick_[h] = c.tick;
      // Read after `now_ns` (and after the bound): the frame's stamp, and the start of the
      // silence a release waits out, are one reading.
      last_command_ns_[h] = base::monotonic_now_ns();
      if (write(c, last_command_ns_[h])) {
        written_.count(c);
        pressing_[h] = carries_force(c);
      } else {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        pressing_[h] = true;  // what the glove holds now is unknown: release it if silence follows
      }
      continue;
    }
    if (!pressing_[h] || (now_ns >= 0 && now_ns - last_command_ns_[h] < kReleaseAfterNs)) continue;
    HapticCommand release;
    release.hand = static_cast<std::uint8_t>(h);
    release.tick = last_tick_[h];
    if (write(release, base::monotonic_now_ns())) {  // otherwise owed still, and tried again each period
      pressing_[h] = false;
      releases_.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void UsbHapticSink::run() noexcept {
  const auto open = [this] {
    const char* why = "";
    return device_.open(why);
  };
  std::int64_t next = base::monotonic_now_ns();
  while (!stop_requested_.load(std::memory_order_acquire)) {
    next += kPeriodNs;
    base::sleep_until_ns(next);
    take_queue();
    const std::int64_t now = base::monotonic_now_ns();
    if (!device_.is_open()) {
      device_.poll_events();  // hotplug arrivals, where libusb has them
      // Nothing of the sink's outlives a transfer call, so a fresh context may always come.
      if (device_.try_reopen(now, open, [] { return true; })) {
        cut_frame_ = false;
        reconnects_.fetch_add(1, std::memory_order_relaxed);
        connected_.store(true, std::memory_order_release);
      }
    }
    write_due(now);
    if (now - next > kPeriodNs) next = now;  // after a long write, do not rush to catch up
  }
  // The last commands (often "release everything") still go out, then whatever is owed.
  take_queue();
  write_due(base::monotonic_now_ns());
  write_due(-1);
}

}  // namespace sculpt::hal
