#include "lcm_haptic_sink.hpp"

#include <array>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/hal/tcpq_probe.hpp"
#include "sculpt/base/clock.hpp"

namespace sculpt::hal {
namespace {

// haptic_command_t is fixed-size (86 bytes with its hash): one stack buffer serves every
// message, so the thread's own work allocates nothing (LCM's publish still does).
constexpr std::size_t kMaxEncodedSize = 256;

}  // namespace

LcmHapticSink::LcmHapticSink(const LcmConfig& config, std::size_t queue_capacity, std::chrono::microseconds poll_period)
    : config_(config), poll_period_(poll_period), queue_(queue_capacity) {}

LcmHapticSink::LcmHapticSink(lcm::LCM& shared, const LcmConfig& config, std::size_t queue_capacity,
                             std::chrono::microseconds poll_period)
    : config_(config), poll_period_(poll_period), lcm_(&shared), queue_(queue_capacity) {}

LcmHapticSink::~LcmHapticSink() { stop(); }

void LcmHapticSink::start() {
  if (thread_.joinable()) throw std::runtime_error("LCM haptic sink: already started");
  if (lcm_ == nullptr) {  // not shared (or closed by a previous stop)
    OpenedLcm opened = open_lcm(config_.url, "LCM haptic sink");
    owned_ = std::move(opened.instance);
    owned_url_ = std::move(opened.url);
    lcm_ = owned_.get();
  }
  next_look_ = std::chrono::steady_clock::now();
  stop_requested_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { run(); });
}

bool LcmHapticSink::may_publish() noexcept {
  if (!owned_ || !is_tcpq_url(owned_url_) || lcm_has_socket(*lcm_)) return true;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_look_) return false;
  next_look_ = now + kTcpqLookPeriod;
  return tcpq_server_answers(owned_url_, kTcpqLookTimeoutMs);
}

void LcmHapticSink::stop() {
  if (!thread_.joinable()) return;
  stop_requested_.store(true, std::memory_order_release);
  thread_.join();
  if (owned_) {
    owned_.reset();
    lcm_ = nullptr;
  }
}

bool LcmHapticSink::send(const HapticCommand& command) noexcept {
  if (queue_.push(command)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

std::size_t LcmHapticSink::drain() noexcept {
  std::size_t sent = 0;
  HapticCommand command;
  sculpt_lcm::haptic_command_t message{};
  std::array<unsigned char, kMaxEncodedSize> buffer;
  while (queue_.pop(command)) {
    ++sent;
    to_lcm(command, base::wall_time_us(), message);
    const int size = message.getEncodedSize();
    const bool encoded =
        size > 0 && static_cast<std::size_t>(size) <= buffer.size() && message.encode(buffer.data(), 0, size) == size;
    if (encoded && may_publish() &&
        lcm_->publish(config_.haptic_channel, buffer.data(), static_cast<unsigned>(size)) == 0) {
      published_.count(command);
    } else {
      publish_errors_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  return sent;
}

void LcmHapticSink::run() noexcept {
  while (!stop_requested_.load(std::memory_order_acquire)) {
    if (drain() == 0) std::this_thread::sleep_for(poll_period_);
  }
  drain();  // the last commands (often "release everything") must still go out
}

}  // namespace sculpt::hal
