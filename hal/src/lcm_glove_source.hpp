#pragma once
// Glove samples received over LCM (sculpt_lcm::glove_sample_t on the scene's glove channel),
// from another process (`sculpt glove-sim`, a glove bridge) or a replayed log.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sequence_tracker.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace lcm {
class LCM;
class Subscription;
struct ReceiveBuffer;
}  // namespace lcm

namespace sculpt::hal {

/// An I/O thread runs LCM's handler loop and queues each valid sample for poll(). Messages
/// that do not decode, or decode to invalid values (hand, kind, non-finite numbers), are
/// counted as framing errors and skipped; the handler never throws. Sequence gaps are counted
/// per hand. State: kConnected from start() (LCM has no connection to lose), kDisconnected
/// while LCM reports errors, kStopped after stop(). An owned tcpq instance whose server went
/// away is replaced by a new one once the server answers again (reopen_lcm(), looked for every
/// kTcpqLookPeriod at the address its host name had at start), so the glove comes back live
/// without a restart; counted as a reconnect once a message or a quiet wait succeeds on it. start() looks first, and stop() never waits on a server that does
/// not answer a look (liblcm's connect and handshake have no timeout: tcpq_probe.hpp).
class LcmGloveSource final : public GloveSource {
 public:
  /// Allocates the queue; start() opens LCM on `config.url`.
  LcmGloveSource(const LcmConfig& config, std::size_t queue_capacity);
  /// Listens on an existing LCM instance instead (not owned; it must outlive this source).
  /// memq:// delivers only within one instance, so deterministic tests publish on it.
  LcmGloveSource(lcm::LCM& shared, const LcmConfig& config, std::size_t queue_capacity);
  ~LcmGloveSource() override;
  LcmGloveSource(const LcmGloveSource&) = delete;
  LcmGloveSource& operator=(const LcmGloveSource&) = delete;

  /// @throw std::runtime_error naming the URL when LCM cannot be opened, or when started twice.
  void start() override;
  void stop() override;
  std::size_t poll(std::span<GloveSample> out) noexcept override;
  SourceCounters counters() const noexcept override;
  SourceState state() const noexcept override { return state_.load(std::memory_order_acquire); }
  const char* name() const noexcept override { return "lcm"; }

 private:
  static void on_message(const lcm::ReceiveBuffer* buffer, const std::string& channel, LcmGloveSource* self);
  void handle(const void* data, std::uint32_t size) noexcept;
  void run() noexcept;
  // A new owned instance in place of one whose tcpq server went away, when the server answers.
  bool reconnect() noexcept;

  LcmConfig config_;
  lcm::LCM* lcm_ = nullptr;  // owned_ or the shared instance
  std::unique_ptr<lcm::LCM> owned_;
  std::string owned_url_;  // the URL owned_ was made on: config_.url, a tcpq host by its address
  lcm::Subscription* subscription_ = nullptr;
  base::SpscQueue<GloveSample> queue_;
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
  SequenceTracker sequence_;  // I/O thread only
};

}  // namespace sculpt::hal
