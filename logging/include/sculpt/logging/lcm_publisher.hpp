#pragma once
// The live publisher: the loop queues plain records, a thread of its own encodes them and
// publishes them on LCM. LCM's publish allocates and may block on a socket, so the loop never
// calls it; it only pushes into bounded SPSC queues, and a full queue is a counted drop.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "sculpt/base/spsc_queue.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/records.hpp"

namespace lcm {
class LCM;
}

namespace sculpt::logging {

struct PublisherConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string fingertip_channel = kFingertipChannel;
  std::string collision_channel = kCollisionChannel;
  std::string tick_channel = kTickChannel;
  std::size_t queue_capacity = 1024;  ///< records per kind between the loop and the thread
  /// How often the thread looks at the queues when they were empty. The loop does not wake
  /// the thread (a wake-up would be a system call in the tick), so this bounds the latency.
  std::chrono::microseconds poll_period{1000};
};

/// Per message kind: what was published, dropped because the queue was full, or failed in
/// encode or publish.
struct ChannelCounters {
  std::uint64_t published = 0;
  std::uint64_t dropped = 0;
  std::uint64_t publish_errors = 0;
};

struct PublisherCounters {
  ChannelCounters fingertip, collision, tick;
  std::uint64_t dropped() const noexcept { return fingertip.dropped + collision.dropped + tick.dropped; }
};

/// Thread-safety: each publish() overload has one producer thread (the loop); start() and
/// stop() belong to the thread that owns the publisher; counters() may be called from anywhere.
class LcmPublisher {
 public:
  /// Allocates the queues; the LCM instance is created by start(), on `config.url`.
  explicit LcmPublisher(PublisherConfig config);
  /// Publishes on an existing instance instead (not owned; it must outlive the publisher).
  /// memq:// delivers only within one instance, so deterministic tests share it this way.
  LcmPublisher(lcm::LCM& shared, PublisherConfig config);
  ~LcmPublisher();
  LcmPublisher(const LcmPublisher&) = delete;
  LcmPublisher& operator=(const LcmPublisher&) = delete;

  /// Opens LCM (when not shared) and starts the thread.
  /// @throw std::runtime_error naming the URL when LCM cannot be opened, or when started twice.
  void start();
  /// Publishes what is still queued, then stops the thread and closes LCM. Idempotent.
  void stop();

  /// Queue a record for publication. Real-time safe: noexcept, wait-free, no allocation.
  /// False when that kind's queue is full (counted as dropped).
  bool publish(const FingertipRecord& record) noexcept;
  bool publish(const CollisionRecord& record) noexcept;
  bool publish(const TickRecord& record) noexcept;

  PublisherCounters counters() const noexcept;
  bool running() const noexcept { return running_.load(std::memory_order_acquire); }

 private:
  struct AtomicChannelCounters {
    std::atomic<std::uint64_t> published{0}, dropped{0}, publish_errors{0};
    ChannelCounters snapshot() const noexcept;
  };
  void run() noexcept;
  std::size_t drain() noexcept;
  template <typename Message>
  void send(const std::string& channel, const Message& message, AtomicChannelCounters& counters) noexcept;

  PublisherConfig config_;
  lcm::LCM* lcm_ = nullptr;  // owned_ or the shared instance
  std::unique_ptr<lcm::LCM> owned_;
  base::SpscQueue<FingertipRecord> fingertips_;
  base::SpscQueue<CollisionRecord> collisions_;
  base::SpscQueue<TickRecord> ticks_;
  AtomicChannelCounters fingertip_counters_, collision_counters_, tick_counters_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
};

}  // namespace sculpt::logging
