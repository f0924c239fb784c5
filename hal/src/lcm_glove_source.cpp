#include "lcm_glove_source.hpp"

#include "sculpt/base/clock.hpp"

#include <time.h>

#include <chrono>
#include <stdexcept>
#include <utility>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/hal/tcpq_probe.hpp"

namespace sculpt::hal {
namespace {

// How long one handleTimeout waits: the latency of stop(), not of the samples (LCM returns
// as soon as a message arrives).
constexpr int kHandleTimeoutMs = 50;
// Back-off while LCM reports errors, so a broken socket does not spin a core.
constexpr std::chrono::milliseconds kErrorBackoff{50};

}  // namespace

LcmGloveSource::LcmGloveSource(const LcmConfig& config, std::size_t queue_capacity)
    : config_(config), queue_(queue_capacity) {}

LcmGloveSource::LcmGloveSource(lcm::LCM& shared, const LcmConfig& config, std::size_t queue_capacity)
    : config_(config), lcm_(&shared), queue_(queue_capacity) {}

LcmGloveSource::~LcmGloveSource() { stop(); }

void LcmGloveSource::start() {
  if (thread_.joinable()) throw std::runtime_error("LCM glove source: already started");
  if (lcm_ == nullptr) {  // not shared (or closed by a previous stop)
    OpenedLcm opened = open_lcm(config_.url, "LCM glove source");
    owned_ = std::move(opened.instance);
    owned_url_ = std::move(opened.url);
    lcm_ = owned_.get();
  }
  // A raw subscription: LCM's typed handlers drop a message that fails to decode with a line
  // on stderr and nothing we could count; this way every bad message is a framing error.
  subscription_ = lcm_->subscribeFunction(config_.glove_channel, &LcmGloveSource::on_message, this);
  if (subscription_ == nullptr) {
    if (owned_) {
      owned_.reset();
      lcm_ = nullptr;
    }
    throw std::runtime_error("LCM glove source: cannot subscribe to '" + config_.glove_channel + "' on '" +
                             config_.url + "'");
  }
  sequence_.reset();
  stop_requested_.store(false, std::memory_order_relaxed);
  state_.store(SourceState::kConnected, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void LcmGloveSource::stop() {
  if (!thread_.joinable()) return;
  stop_requested_.store(true, std::memory_order_release);
  thread_.join();
  if (owned_) {
    destroy_without_waiting(std::move(owned_), owned_url_, {subscription_});
    lcm_ = nullptr;
  } else {
    lcm_->unsubscribe(subscription_);
  }
  subscription_ = nullptr;
  state_.store(SourceState::kStopped, std::memory_order_release);
}

std::size_t LcmGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters LcmGloveSource::counters() const noexcept { return counters_.snapshot(); }

void LcmGloveSource::on_message(const lcm::ReceiveBuffer* buffer, const std::string& /*channel*/,
                                LcmGloveSource* self) {
  self->handle(buffer->data, buffer->data_size);
}

void LcmGloveSource::handle(const void* data, std::uint32_t size) noexcept {
  const std::int64_t received_ns = base::monotonic_now_ns();
  sculpt_lcm::glove_sample_t message;
  // decode checks the type's fingerprint and every length; a message with bytes left over is
  // not a glove_sample_t either.
  const int used = message.decode(data, 0, static_cast<int>(size));
  GloveSample sample;
  if (used < 0 || static_cast<std::uint32_t>(used) != size || !from_lcm(message, sample)) {
    counters_.framing_errors.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  sample.receive_time_ns = received_ns;

  // Wrap-around aware; a step back (device restart, reordered datagram) counts nothing.
  if (const std::uint32_t missing = sequence_.observe(sample.hand, sample.sequence); missing > 0) {
    counters_.sequence_gaps.fetch_add(missing, std::memory_order_relaxed);
  }

  if (queue_.push(sample)) {
    counters_.samples.fetch_add(1, std::memory_order_relaxed);
  } else {
    counters_.overflows.fetch_add(1, std::memory_order_relaxed);
  }
}

bool LcmGloveSource::reconnect() noexcept {
  std::unique_ptr<lcm::LCM> fresh = reopen_lcm(owned_url_);
  if (!fresh) return false;
  lcm::Subscription* subscription = nullptr;
  try {
    subscription = fresh->subscribeFunction(config_.glove_channel, &LcmGloveSource::on_message, this);
  } catch (...) {  // its allocation: the server is looked for again at the next look
  }
  if (subscription == nullptr || !lcm_has_socket(*fresh)) {
    destroy_without_waiting(std::move(fresh), owned_url_, {subscription});
    return false;
  }
  // The old instance goes, and its subscription with it, without waiting on its server.
  std::swap(owned_, fresh);
  lcm_ = owned_.get();
  lcm::Subscription* const old_subscription = std::exchange(subscription_, subscription);
  destroy_without_waiting(std::move(fresh), owned_url_, {old_subscription});
  return true;
}

void LcmGloveSource::run() noexcept {
  auto next_look = std::chrono::steady_clock::now();
  while (!stop_requested_.load(std::memory_order_acquire)) {
    if (lcm_handle_within(*lcm_, kHandleTimeoutMs) < 0) {
      if (state_.exchange(SourceState::kDisconnected) != SourceState::kDisconnected) {
        counters_.disconnects.fetch_add(1, std::memory_order_relaxed);
      }
      // An owned tcpq instance without a socket lost its server: a new one once it answers.
      if (owned_ && !lcm_has_socket(*lcm_) && std::chrono::steady_clock::now() >= next_look) {
        next_look = std::chrono::steady_clock::now() + kTcpqLookPeriod;
        if (reconnect()) continue;
      }
      std::this_thread::sleep_for(kErrorBackoff);
      continue;
    }
    SourceState expected = SourceState::kDisconnected;
    if (state_.compare_exchange_strong(expected, SourceState::kConnected)) {
      counters_.reconnects.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

}  // namespace sculpt::hal
