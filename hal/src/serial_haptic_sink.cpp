#include "serial_haptic_sink.hpp"

#include "sculpt/base/clock.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <string>
#include <system_error>

namespace sculpt::hal {

SerialHapticSink::SerialHapticSink(const SerialConfig& config, std::size_t queue_capacity, BacklogProbe backlog)
    : config_(config), queue_(queue_capacity == 0 ? 2 : queue_capacity), backlog_(backlog) {
  validate_serial_config(config_, "serial haptic sink");
  if (queue_capacity == 0) {
    throw std::invalid_argument("serial haptic sink " + config_.device + ": queue_capacity must be > 0");
  }
  wake_fd_ = make_wake_fd(std::string("serial haptic sink ") + config_.device);
}

SerialHapticSink::~SerialHapticSink() {
  stop();
  ::close(wake_fd_);
}

void SerialHapticSink::start() {
  if (thread_.joinable()) {
    throw std::runtime_error("serial haptic sink " + config_.device + ": already started");
  }
  require_character_device_if_present(config_.device, "serial haptic sink");
  stop_requested_.store(false, std::memory_order_relaxed);
  sequence_ = 0;
  // One attempt here; a rate the device refuses stops the start, as the glove source's does.
  connect();
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error& e) {
    port_.close();
    connected_.store(false, std::memory_order_release);
    throw std::runtime_error("serial haptic sink " + config_.device + ": cannot start I/O thread: " + e.what());
  }
}

void SerialHapticSink::stop() {
  if (thread_.joinable()) {
    stop_requested_.store(true, std::memory_order_release);
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof one);
    thread_.join();
  }
  port_.close();
  connected_.store(false, std::memory_order_release);
}

bool SerialHapticSink::send(const HapticCommand& command) noexcept {
  if (!queue_.push(command)) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  // Never blocks: the eventfd is non-blocking, and a saturated counter still means "wake".
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof one);
  return true;
}

std::uint64_t SerialHapticSink::dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

std::uint64_t SerialHapticSink::frames_written() const noexcept { return written_.total(); }

bool SerialHapticSink::connected() const noexcept { return connected_.load(std::memory_order_acquire); }

bool SerialHapticSink::try_connect() noexcept {
  try {
    return connect();
  } catch (...) {
    port_.close();
    return false;
  }
}

bool SerialHapticSink::connect() {
  std::string error;
  if (!port_.try_open(config_.device, config_.baud, error)) return false;
  connected_.store(true, std::memory_order_release);
  return true;
}

bool SerialHapticSink::write_frame(std::span<const std::uint8_t> frame, std::size_t& sent) noexcept {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kWriteTimeoutMs);
  while (!frame.empty()) {
    const IoResult r = port_.write(frame);
    if (r.status == IoStatus::kGone) {
      port_.close();
      connected_.store(false, std::memory_order_release);
      return false;
    }
    if (r.status == IoStatus::kOk) {
      frame = frame.subspan(r.bytes);
      sent += r.bytes;
      continue;
    }
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd out{port_.fd(), POLLOUT, 0};
    ::poll(&out, 1, static_cast<int>(left.count()));
    if ((out.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
      port_.close();
      connected_.store(false, std::memory_order_release);
      return false;
    }
  }
  return true;
}

void SerialHapticSink::deliver(const HapticCommand& command) noexcept {
  if (!port_.is_open()) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const std::size_t n =
      encode_haptic_frame(command, sequence_++, base::monotonic_now_us(), std::span<std::uint8_t>(frame_).subspan(1));
  const std::size_t begin = cut_frame_on_line_ ? 0 : 1;  // frame_[0] is a zero delimiter
  std::size_t sent = 0;
  if (write_frame(std::span<const std::uint8_t>(frame_.data() + begin, 1 + n - begin), sent)) {
    written_.count(command);
    cut_frame_on_line_ = false;
  } else {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    cut_frame_on_line_ = cut_frame_on_line_ || sent > 0;
  }
}

bool SerialHapticSink::drain_queue() noexcept {
  // Everything queued while the last frame was on the wire is older than the newest command
  // of its hand: only that one is sent (see the class comment).
  HapticCommand command;
  while (queue_.pop(command)) {
    const std::size_t hand = command.hand < kHands ? command.hand : kHands - 1;
    if (holding_[hand]) superseded_.fetch_add(1, std::memory_order_relaxed);
    held_[hand] = command;
    holding_[hand] = true;
  }
  bool waiting = false;
  for (std::size_t hand = 0; hand < kHands; ++hand) {
    if (!holding_[hand]) continue;
    if (port_.is_open() && backlog_(port_.fd()) > kMaxBacklogBytes) {
      waiting = true;  // the driver still holds a frame's worth: write when it has sent it
      continue;
    }
    deliver(held_[hand]);
    holding_[hand] = false;
  }
  return waiting;
}

void SerialHapticSink::run() noexcept {
  using Clock = std::chrono::steady_clock;
  const auto interval = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double, std::milli>(config_.reconnect_interval_ms));
  auto next_attempt = Clock::now() + interval;
  bool held_back = false;
  while (!stop_requested_.load(std::memory_order_acquire)) {
    int timeout_ms = held_back ? 1 : kSerialPollTimeoutMs;
    if (!port_.is_open()) {
      const auto now = Clock::now();
      if (now >= next_attempt) {
        if (!try_connect()) next_attempt = now + interval;
      }
      if (!port_.is_open()) {
        const auto wait = std::chrono::ceil<std::chrono::milliseconds>(next_attempt - Clock::now());
        timeout_ms = static_cast<int>(std::clamp<std::int64_t>(wait.count(), 1, kSerialPollTimeoutMs));
      }
    }
    // Events 0 on the device: poll still reports POLLHUP / POLLERR, which is all we want from
    // it; the writer never reads.
    pollfd fds[2] = {{wake_fd_, POLLIN, 0}, {port_.fd(), 0, 0}};
    const int ready = ::poll(fds, port_.is_open() ? 2 : 1, timeout_ms);
    if (ready < 0 && errno != EINTR) continue;
    if (port_.is_open() && (fds[1].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
      port_.close();
      connected_.store(false, std::memory_order_release);
      next_attempt = Clock::now() + interval;
    }
    if ((fds[0].revents & POLLIN) != 0) {
      std::uint64_t value = 0;
      [[maybe_unused]] const ssize_t n = ::read(wake_fd_, &value, sizeof value);
    }
    // A held command is retried after about one frame time at 921,600 baud.
    held_back = drain_queue();
    if (!port_.is_open() && connected_.load(std::memory_order_relaxed)) {
      connected_.store(false, std::memory_order_release);
    }
  }
}

}  // namespace sculpt::hal
