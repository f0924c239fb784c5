#include "can_glove_source.hpp"

#include "sculpt/base/clock.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sculpt::hal {
namespace {

std::string errno_text(int e) { return std::strerror(e); }

}  // namespace

CanConfig checked_can_config(const CanConfig& config, const std::string& section) {
  if (config.interface.empty()) throw std::invalid_argument(section + ".interface: empty");
  if (config.interface.size() >= IFNAMSIZ)
    throw std::invalid_argument(section + ".interface: '" + config.interface + "' is longer than " +
                                std::to_string(IFNAMSIZ - 1) + " characters");
  if (config.base_id > kCanMaxExtendedId - kCanIdSpan)
    throw std::invalid_argument(section + ".base_id: " + std::to_string(config.base_id) + " leaves no room for the " +
                                std::to_string(kCanIdSpan) + " ids after it below 0x1FFFFFFF");
  return config;
}

int open_can_socket(const std::string& interface, bool fd, bool error_frames) {
  const int s = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (s < 0) {
    const int e = errno;
    if (e == EAFNOSUPPORT || e == EPROTONOSUPPORT)
      throw std::runtime_error("socketcan: AF_CAN is not available on this kernel (" + errno_text(e) +
                               "; load the can and can_raw modules)");
    throw std::runtime_error("socketcan: cannot open a raw CAN socket for '" + interface + "' (" + errno_text(e) + ")");
  }
  const auto fail = [&](const std::string& what, int e) {
    ::close(s);
    throw std::runtime_error("socketcan: " + what + " (" + errno_text(e) + ")");
  };
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) {
    ::close(s);
    throw std::runtime_error("socketcan: no interface '" + interface + "'");
  }
  if (fd) {
    const int on = 1;
    if (::setsockopt(s, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) != 0)
      fail("interface '" + interface + "': CAN FD frames not supported by this kernel", errno);
  }
  if (error_frames) {
    const can_err_mask_t mask = CAN_ERR_MASK;
    if (::setsockopt(s, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof mask) != 0)
      fail("interface '" + interface + "': cannot receive error frames", errno);
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(index);
  if (::bind(s, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    fail("cannot bind to interface '" + interface + "'", errno);
  return s;
}

CanGloveSource::CanGloveSource(const CanConfig& config, std::size_t queue_capacity)
    : config_(checked_can_config(config, "glove.can")),
      queue_(queue_capacity),
      decoders_{CanSampleDecoder(config.base_id, 0, config.fd), CanSampleDecoder(config.base_id, 1, config.fd)} {}

CanGloveSource::~CanGloveSource() { stop(); }

void CanGloveSource::start() {
  if (thread_.joinable()) return;
  state_.store(SourceState::kConnecting, std::memory_order_release);
  try {
    socket_ = open_can_socket(config_.interface, config_.fd, true);
  } catch (...) {
    state_.store(SourceState::kStopped, std::memory_order_release);
    throw;
  }
  wake_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_ < 0) {
    const int e = errno;
    ::close(socket_);
    socket_ = -1;
    state_.store(SourceState::kStopped, std::memory_order_release);
    throw std::runtime_error("socketcan: '" + config_.interface + "': eventfd failed (" + errno_text(e) + ")");
  }
  for (auto& d : decoders_) d.reset();
  stop_requested_.store(false, std::memory_order_relaxed);
  state_.store(SourceState::kConnected, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void CanGloveSource::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (wake_ >= 0) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(wake_, &one, sizeof one);
  }
  if (thread_.joinable()) thread_.join();
  if (socket_ >= 0) ::close(socket_);
  if (wake_ >= 0) ::close(wake_);
  socket_ = wake_ = -1;
  state_.store(SourceState::kStopped, std::memory_order_release);
}

void CanGloveSource::on_frame(const CanFrame& frame) noexcept {
  for (std::size_t h = 0; h < kHands; ++h) {
    GloveSample sample;
    const CanFeedResult r = decoders_[h].feed(frame, sample);
    if (r == CanFeedResult::kIgnored) continue;
    if (r == CanFeedResult::kComplete) {
      sample.receive_time_ns = base::monotonic_now_ns();
      if (queue_.push(sample))
        counters_.samples.fetch_add(1, std::memory_order_relaxed);
      else
        counters_.overflows.fetch_add(1, std::memory_order_relaxed);
    }
    // Publish the decoder's fault counts as deltas: the decoder's own counters are the I/O
    // thread's, the atomics everyone's.
    const CanDecoderCounters& now = decoders_[h].counters();
    CanDecoderCounters& seen = reported_[h];
    counters_.framing_errors.fetch_add(now.framing_errors - seen.framing_errors, std::memory_order_relaxed);
    counters_.crc_errors.fetch_add(now.crc_errors - seen.crc_errors, std::memory_order_relaxed);
    counters_.sequence_gaps.fetch_add(now.sequence_gaps - seen.sequence_gaps, std::memory_order_relaxed);
    seen = now;
    return;
  }
}

bool CanGloveSource::reopen_socket() noexcept {
  try {
    const int fresh = open_can_socket(config_.interface, config_.fd, true);
    ::close(socket_);
    socket_ = fresh;
    return true;
  } catch (...) {  // not there yet (or no memory for the message): try again later
    return false;
  }
}

void CanGloveSource::run() noexcept {
  pollfd fds[2] = {{socket_, POLLIN, 0}, {wake_, POLLIN, 0}};
  canfd_frame raw{};
  while (!stop_requested_.load(std::memory_order_acquire)) {
    fds[0].revents = fds[1].revents = 0;
    const int ready = ::poll(fds, 2, -1);
    if (ready < 0) continue;  // EINTR
    if (fds[1].revents != 0) break;
    if (fds[0].revents == 0) continue;
    const ssize_t n = ::read(socket_, &raw, sizeof raw);
    if (n < 0) {
      const int e = errno;
      if (e == EINTR || e == EAGAIN) continue;
      // ENETDOWN: the interface went down; the socket stays bound and reads again when it
      // comes back up. ENODEV: the interface is gone (a USB adapter unplugged); the kernel
      // unbinds the socket for good, so it is opened again until an interface of that name
      // is back.
      if (state_.exchange(SourceState::kDisconnected, std::memory_order_acq_rel) == SourceState::kConnected)
        counters_.disconnects.fetch_add(1, std::memory_order_relaxed);
      pollfd wake = {wake_, POLLIN, 0};
      if (e != ENODEV) {
        ::poll(&wake, 1, 200);  // do not spin on a dead interface
        continue;
      }
      while (!stop_requested_.load(std::memory_order_acquire) && !reopen_socket()) ::poll(&wake, 1, 200);
      fds[0].fd = socket_;
      continue;
    }
    if (state_.load(std::memory_order_relaxed) == SourceState::kDisconnected) {
      state_.store(SourceState::kConnected, std::memory_order_release);
      counters_.reconnects.fetch_add(1, std::memory_order_relaxed);
    }
    if (n != static_cast<ssize_t>(CAN_MTU) && n != static_cast<ssize_t>(CANFD_MTU)) {
      counters_.framing_errors.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (raw.can_id & CAN_ERR_FLAG) {
      counters_.error_frames.fetch_add(1, std::memory_order_relaxed);
      if (raw.can_id & CAN_ERR_BUSOFF) counters_.bus_off.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (raw.can_id & CAN_RTR_FLAG) continue;
    CanFrame frame;
    frame.id = (raw.can_id & CAN_EFF_FLAG) ? (raw.can_id & CAN_EFF_MASK) : (raw.can_id & CAN_SFF_MASK);
    frame.fd = n == static_cast<ssize_t>(CANFD_MTU);
    frame.len = static_cast<std::uint8_t>(std::min<std::size_t>(raw.len, frame.fd ? kCanFdLen : kCanClassicLen));
    std::memcpy(frame.data.data(), raw.data, frame.len);
    on_frame(frame);
  }
}

std::size_t CanGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters CanGloveSource::counters() const noexcept { return counters_.snapshot(); }

}  // namespace sculpt::hal
