#include "can_haptic_sink.hpp"

#include "sculpt/base/clock.hpp"

#include <linux/can.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "can_glove_source.hpp"

namespace sculpt::hal {
namespace {

constexpr long kWakeNs = 1'000'000;
constexpr std::int64_t kReopenIntervalNs = 200'000'000;  // how often a vanished interface is looked for

}  // namespace

CanHapticSink::CanHapticSink(const CanConfig& config, std::size_t queue_capacity)
    : config_(checked_can_config(config, "haptic.can")), queue_(queue_capacity) {}

CanHapticSink::~CanHapticSink() { stop(); }

void CanHapticSink::start() {
  if (thread_.joinable()) return;
  socket_ = open_can_socket(config_.interface, config_.fd, false);
  stop_requested_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { run(); });
}

void CanHapticSink::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (socket_ >= 0) ::close(socket_);
  socket_ = -1;
}

bool CanHapticSink::send(const HapticCommand& command) noexcept {
  if (command.hand < kHands && queue_.push(command)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool CanHapticSink::write_command(const HapticCommand& command) noexcept {
  std::array<CanFrame, kCanMaxHapticFrames> frames;
  const std::size_t n = encode_haptic(command, config_.base_id, config_.fd, frames);
  for (std::size_t i = 0; i < n; ++i) {
    const CanFrame& f = frames[i];
    canfd_frame raw{};
    raw.can_id = f.id > kCanMaxStandardId ? (f.id | CAN_EFF_FLAG) : f.id;
    raw.len = f.len;
    std::memcpy(raw.data, f.data.data(), f.len);
    const std::size_t mtu = f.fd ? CANFD_MTU : CAN_MTU;  // a classic can_frame is the FD one's prefix
    // Never waits: a bus that does not drain (bus-off, an unplugged cable with a long transmit
    // queue) would otherwise hold this thread in write(), and stop() with it. A full queue
    // (EAGAIN, ENOBUFS) drops the command, counted, and the next newest one tries again.
    ssize_t w;
    do {
      w = ::send(socket_, &raw, mtu, MSG_DONTWAIT);
    } while (w < 0 && errno == EINTR);
    // A half-sent command is broken on the wire; the receiver's decoder counts it.
    if (w != static_cast<ssize_t>(mtu)) {
      // The interface went away (ENODEV once, then ENXIO: the kernel unbound the socket).
      if (w < 0 && (errno == ENODEV || errno == ENXIO)) interface_gone_ = true;
      return false;
    }
  }
  return n > 0;
}

void CanHapticSink::run() noexcept {
  std::int64_t next = base::monotonic_now_ns();
  std::int64_t next_reopen = next;
  std::array<HapticCommand, kHands> newest{};
  std::array<bool, kHands> have{};
  while (!stop_requested_.load(std::memory_order_acquire)) {
    next += kWakeNs;
    base::sleep_until_ns(next);
    HapticCommand c;
    while (queue_.pop(c)) {
      if (have[c.hand]) superseded_.fetch_add(1, std::memory_order_relaxed);
      newest[c.hand] = c;
      have[c.hand] = true;
    }
    if (interface_gone_ && next >= next_reopen) {
      next_reopen = next + kReopenIntervalNs;
      try {
        const int fresh = open_can_socket(config_.interface, config_.fd, false);
        ::close(socket_);
        socket_ = fresh;
        interface_gone_ = false;
      } catch (...) {  // not back yet: the commands meanwhile are dropped
      }
    }
    for (std::size_t h = 0; h < kHands; ++h) {
      if (!have[h]) continue;
      have[h] = false;
      if (write_command(newest[h]))
        sent_.count(newest[h]);
      else
        dropped_.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

}  // namespace sculpt::hal
