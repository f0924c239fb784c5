#include "sculpt/logging/lcm_publisher.hpp"

#include <array>
#include <stdexcept>
#include <utility>

#include <lcm/lcm-cpp.hpp>

namespace sculpt::logging {

ChannelCounters LcmPublisher::AtomicChannelCounters::snapshot() const noexcept {
  return {published.load(std::memory_order_relaxed), dropped.load(std::memory_order_relaxed),
          publish_errors.load(std::memory_order_relaxed)};
}

LcmPublisher::LcmPublisher(PublisherConfig config)
    : config_(std::move(config)),
      fingertips_(config_.queue_capacity),
      collisions_(config_.queue_capacity),
      ticks_(config_.queue_capacity) {}

LcmPublisher::LcmPublisher(lcm::LCM& shared, PublisherConfig config) : LcmPublisher(std::move(config)) {
  lcm_ = &shared;
}

LcmPublisher::~LcmPublisher() { stop(); }

void LcmPublisher::start() {
  if (thread_.joinable()) throw std::runtime_error("LcmPublisher: already started");
  if (lcm_ == nullptr) {  // not shared (or closed by a previous stop)
    owned_ = std::make_unique<lcm::LCM>(config_.url);
    if (!owned_->good()) {
      owned_.reset();
      throw std::runtime_error("LcmPublisher: cannot open LCM at '" + config_.url + "'");
    }
    lcm_ = owned_.get();
  }
  stop_requested_.store(false, std::memory_order_relaxed);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void LcmPublisher::stop() {
  if (!thread_.joinable()) return;
  stop_requested_.store(true, std::memory_order_release);
  thread_.join();
  running_.store(false, std::memory_order_release);
  if (owned_) {
    owned_.reset();
    lcm_ = nullptr;
  }
}

bool LcmPublisher::publish(const FingertipRecord& record) noexcept {
  if (fingertips_.push(record)) return true;
  fingertip_counters_.dropped.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool LcmPublisher::publish(const CollisionRecord& record) noexcept {
  if (collisions_.push(record)) return true;
  collision_counters_.dropped.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool LcmPublisher::publish(const TickRecord& record) noexcept {
  if (ticks_.push(record)) return true;
  tick_counters_.dropped.fetch_add(1, std::memory_order_relaxed);
  return false;
}

PublisherCounters LcmPublisher::counters() const noexcept {
  return {fingertip_counters_.snapshot(), collision_counters_.snapshot(), tick_counters_.snapshot()};
}

template <typename Message>
void LcmPublisher::send(const std::string& channel, const Message& message, AtomicChannelCounters& counters) noexcept {
  std::array<unsigned char, kMaxEncodedSize> buffer;
  const int size = message.getEncodedSize();
  const bool encoded =
      size > 0 && static_cast<std::size_t>(size) <= buffer.size() && message.encode(buffer.data(), 0, size) == size;
  // lcm_publish returns nonzero when the transport refused the message (e.g. no route).
  if (encoded && lcm_->publish(channel, buffer.data(), static_cast<unsigned>(size)) == 0) {
    counters.published.fetch_add(1, std::memory_order_relaxed);
  } else {
    counters.publish_errors.fetch_add(1, std::memory_order_relaxed);
  }
}

std::size_t LcmPublisher::drain() noexcept {
  std::size_t sent = 0;
  // Collisions first: they are the edit history, the others are for watching.
  CollisionRecord collision;
  sculpt_lcm::collision_event_t collision_message{};
  while (collisions_.pop(collision)) {
    to_lcm(collision, collision_message);
    send(config_.collision_channel, collision_message, collision_counters_);
    ++sent;
  }
  FingertipRecord fingertip;
  sculpt_lcm::fingertip_state_t fingertip_message{};
  while (fingertips_.pop(fingertip)) {
    to_lcm(fingertip, fingertip_message);
    send(config_.fingertip_channel, fingertip_message, fingertip_counters_);
    ++sent;
  }
  TickRecord tick;
  sculpt_lcm::tick_stats_t tick_message{};
  while (ticks_.pop(tick)) {
    to_lcm(tick, tick_message);
    send(config_.tick_channel, tick_message, tick_counters_);
    ++sent;
  }
  return sent;
}

void LcmPublisher::run() noexcept {
  while (!stop_requested_.load(std::memory_order_acquire)) {
    if (drain() == 0) std::this_thread::sleep_for(config_.poll_period);
  }
  // What the loop queued before stop() is still published: the last ticks matter most.
  drain();
}

}  // namespace sculpt::logging
