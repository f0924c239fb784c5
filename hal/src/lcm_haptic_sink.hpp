#pragma once
// Haptic commands published over LCM (sculpt_lcm::haptic_command_t on the scene's haptic
// channel), for a glove bridge process to forward to the actuators.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "delivery_counts.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace lcm {
class LCM;
}

namespace sculpt::hal {

/// send() only queues; a thread of the sink's own encodes and publishes, because LCM's
/// publish allocates and may block. The thread looks at the queue every `poll_period` when it
/// was empty (the loop does not wake it: that would be a system call in the tick).
class LcmHapticSink final : public HapticSink {
 public:
  LcmHapticSink(const LcmConfig& config, std::size_t queue_capacity,
                std::chrono::microseconds poll_period = std::chrono::microseconds(500));
  /// Publishes on an existing LCM instance (not owned; it must outlive this sink), for memq://.
  LcmHapticSink(lcm::LCM& shared, const LcmConfig& config, std::size_t queue_capacity,
                std::chrono::microseconds poll_period = std::chrono::microseconds(500));
  ~LcmHapticSink() override;
  LcmHapticSink(const LcmHapticSink&) = delete;
  LcmHapticSink& operator=(const LcmHapticSink&) = delete;

  /// @throw std::runtime_error naming the URL when LCM cannot be opened, or when started twice.
  void start() override;
  /// Publishes what is still queued, then stops. Idempotent.
  void stop() override;
  bool send(const HapticCommand& command) noexcept override;
  /// Commands refused because the queue was full.
  std::uint64_t dropped() const noexcept override { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t published() const noexcept { return published_.total(); }
  std::uint64_t delivered() const noexcept override { return published(); }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override { return published_.in_contact(hand); }
  /// Commands that failed to encode, that LCM refused to publish, or that were not published
  /// because the tcpq server had gone (may_publish()).
  std::uint64_t publish_errors() const noexcept { return publish_errors_.load(std::memory_order_relaxed); }
  const char* name() const noexcept override { return "lcm"; }

 private:
  void run() noexcept;
  std::size_t drain() noexcept;
  // Whether to publish now. liblcm's tcpq instance reconnects inside publish() once its server
  // hung up, and its connect and handshake have no timeout: a server whose process was stopped
  // held the sink's thread, and so stop(), for ever. Such an instance publishes again only after
  // its server answered a look (at most one every second); its commands until then are errors.
  bool may_publish() noexcept;

  LcmConfig config_;
  std::chrono::microseconds poll_period_;
  lcm::LCM* lcm_ = nullptr;  // owned_ or the shared instance
  std::unique_ptr<lcm::LCM> owned_;
  std::string owned_url_;  // the URL owned_ was made on: config_.url, a tcpq host by its address
  base::SpscQueue<HapticCommand> queue_;
  std::atomic<std::uint64_t> dropped_{0}, publish_errors_{0};
  DeliveryCounts published_;
  std::chrono::steady_clock::time_point next_look_{};  // the sink thread's
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
};

}  // namespace sculpt::hal
