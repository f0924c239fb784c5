#include "serial_glove_source.hpp"

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
#include <system_error>

namespace sculpt::hal {
namespace {

void drain_eventfd(int fd) noexcept {
  std::uint64_t value = 0;
  while (::read(fd, &value, sizeof value) > 0) {
  }
}

}  // namespace

SerialGloveSource::SerialGloveSource(const SerialConfig& config, std::size_t queue_capacity)
    : config_(config), queue_(queue_capacity == 0 ? 2 : queue_capacity) {
  validate_serial_config(config_, "serial glove");
  if (queue_capacity == 0) {
    throw std::invalid_argument("serial glove " + config_.device + ": queue_capacity must be > 0");
  }
  wake_fd_ = make_wake_fd(std::string("serial glove ") + config_.device);
}

SerialGloveSource::~SerialGloveSource() {
  stop();
  ::close(wake_fd_);
}

void SerialGloveSource::start() {
  if (thread_.joinable()) throw std::runtime_error("serial glove " + config_.device + ": already started");
  require_character_device_if_present(config_.device, "serial glove");
  drain_eventfd(wake_fd_);
  stop_requested_.store(false, std::memory_order_relaxed);
  ever_connected_ = false;
  state_.store(SourceState::kConnecting, std::memory_order_release);
  // One attempt here, so a glove that is already plugged in is connected when start() returns.
  // A rate the device refuses, or another reader holding it, stops the start
  // (SerialPort::RateRefused, SerialPort::InUse: the message names the device); later attempts
  // keep trying, the message in last_error().
  try {
    connect();
  } catch (...) {
    state_.store(SourceState::kStopped, std::memory_order_release);
    throw;
  }
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error& e) {
    port_.close();
    state_.store(SourceState::kStopped, std::memory_order_release);
    throw std::runtime_error("serial glove " + config_.device + ": cannot start I/O thread: " + e.what());
  }
}

void SerialGloveSource::stop() {
  if (thread_.joinable()) {
    stop_requested_.store(true, std::memory_order_release);
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof one);
    thread_.join();
  }
  port_.close();
  decoder_.reset();
  state_.store(SourceState::kStopped, std::memory_order_release);
}

std::size_t SerialGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters SerialGloveSource::counters() const noexcept { return counters_.snapshot(); }

SourceState SerialGloveSource::state() const noexcept { return state_.load(std::memory_order_acquire); }

std::string SerialGloveSource::last_error() const {
  const std::lock_guard lock(error_mutex_);
  return last_error_;
}

bool SerialGloveSource::try_connect() noexcept {
  // Not the real-time path: strings may allocate here; nothing may escape the thread.
  try {
    return connect();
  } catch (const std::exception& e) {
    port_.close();
    try {
      const std::lock_guard lock(error_mutex_);
      last_error_ = e.what();
    } catch (...) {  // no memory for the message: the failed attempt is all there is to say
    }
    return false;
  } catch (...) {
    port_.close();
    return false;
  }
}

bool SerialGloveSource::connect() {
  {
    std::string error;
    // The reader takes the device's lock: a second station (or any program locking it) on the
    // same glove would split its bytes with this one.
    if (!port_.try_open(config_.device, config_.baud, error, /*exclusive=*/true)) {
      const std::lock_guard lock(error_mutex_);
      last_error_ = std::move(error);
      return false;
    }
    const std::lock_guard lock(error_mutex_);
    last_error_.clear();
  }
  // Bytes from before the drop must not be glued to the new connection's first frame.
  decoder_.reset();
  if (ever_connected_) counters_.reconnects.fetch_add(1, std::memory_order_relaxed);
  ever_connected_ = true;
  state_.store(SourceState::kConnected, std::memory_order_release);
  return true;
}

void SerialGloveSource::disconnect() noexcept {
  port_.close();
  decoder_.reset();
  counters_.disconnects.fetch_add(1, std::memory_order_relaxed);
  state_.store(SourceState::kDisconnected, std::memory_order_release);
}

void SerialGloveSource::handle_bytes(std::span<const std::uint8_t> bytes) noexcept {
  decoder_.feed(bytes, [this](const DecodedFrame& frame) {
    if (frame.type != DecodedFrame::Type::kSample) return;  // haptic frames are not ours
    GloveSample sample = frame.sample;
    const std::uint32_t missing = tracker_.observe(sample.hand, sample.sequence);
    if (missing != 0) counters_.sequence_gaps.fetch_add(missing, std::memory_order_relaxed);
    sample.receive_time_ns = base::monotonic_now_ns();
    if (queue_.push(sample)) {
      counters_.samples.fetch_add(1, std::memory_order_relaxed);
    } else {
      counters_.overflows.fetch_add(1, std::memory_order_relaxed);
    }
  });
  // Mirrored, so counters() can be read from any thread without touching the decoder.
  const DecoderCounters& d = decoder_.counters();
  counters_.crc_errors.store(d.crc_errors, std::memory_order_relaxed);
  counters_.framing_errors.store(d.framing_errors, std::memory_order_relaxed);
}

void SerialGloveSource::run() noexcept {
  using Clock = std::chrono::steady_clock;
  const auto interval = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double, std::milli>(config_.reconnect_interval_ms));
  auto next_attempt = Clock::now() + interval;
  while (!stop_requested_.load(std::memory_order_acquire)) {
    if (!port_.is_open()) {
      const auto now = Clock::now();
      if (now >= next_attempt) {
        if (try_connect()) continue;
        next_attempt = now + interval;
      }
      const auto wait = std::chrono::ceil<std::chrono::milliseconds>(next_attempt - Clock::now());
      pollfd wake{wake_fd_, POLLIN, 0};
      ::poll(&wake, 1, static_cast<int>(std::clamp<std::int64_t>(wait.count(), 1, kSerialPollTimeoutMs)));
      continue;
    }
    pollfd fds[2] = {{port_.fd(), POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    const int ready = ::poll(fds, 2, kSerialPollTimeoutMs);
    if (ready < 0) {
      if (errno == EINTR) continue;
      disconnect();
      next_attempt = Clock::now() + interval;
      continue;
    }
    if (ready == 0 || fds[1].revents != 0) continue;  // timeout, or stop() woke us
    const short revents = fds[0].revents;
    if (revents == 0) continue;
    bool gone = (revents & POLLNVAL) != 0;
    if (!gone) {
      // After POLLIN or POLLHUP a read of nothing means the terminal was hung up: with
      // VMIN = VTIME = 0 that is how a vanished tty reads (a pty whose master closed gives EIO).
      const IoResult r = port_.read(read_buffer_);
      if (r.status == IoStatus::kOk) {
        handle_bytes(std::span<const std::uint8_t>(read_buffer_.data(), r.bytes));
      } else {
        gone = true;
      }
    }
    if (gone) {
      disconnect();
      next_attempt = Clock::now() + interval;
    }
  }
}

}  // namespace sculpt::hal
