#pragma once
// The simulated glove as a real backend: a SimScript played on its own thread in real time.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sculpt/hal/sim_script.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// Plays a SimScript in real time. Its thread sleeps to absolute CLOCK_MONOTONIC deadlines
/// (clock_nanosleep, TIMER_ABSTIME) and delivers each sample when
/// now >= start + device_time + latency, stamping receive_time_ns at delivery; a full queue
/// drops the sample and counts an overflow. Sequence gaps (the script's dropouts) are counted
/// as a real backend's decoder would count them.
///
/// State is kConnected from start() to stop(). When the script ends the thread simply stops
/// producing, like a glove that stops sending: the state stays kConnected and the loop's
/// staleness timeout releases the forces; finished() tells the two apart for tools and tests.
class SimGloveSource final : public GloveSource {
 public:
  /// @throw std::invalid_argument from SimScript when the config is invalid.
  explicit SimGloveSource(const SimConfig& config, std::size_t queue_capacity = 1024);
  ~SimGloveSource() override;
  SimGloveSource(const SimGloveSource&) = delete;
  SimGloveSource& operator=(const SimGloveSource&) = delete;

  /// Rewinds the script and starts its thread (device time 0 = now). No-op while the script is
  /// still playing; after it finished, plays it again.
  /// @throw std::system_error if the thread cannot be created.
  void start() override;
  void stop() override;
  std::size_t poll(std::span<GloveSample> out) noexcept override;
  SourceCounters counters() const noexcept override;
  SourceState state() const noexcept override { return state_.load(std::memory_order_acquire); }
  const char* name() const noexcept override { return "sim"; }

  /// True once the script has delivered (or dropped) its last sample.
  bool finished() const noexcept { return finished_.load(std::memory_order_acquire); }

 private:
  void run() noexcept;

  SimScript script_;
  std::int64_t latency_ns_;
  base::SpscQueue<GloveSample> queue_;
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> finished_{false};
  std::int64_t start_ns_ = 0;
  std::thread thread_;
};

}  // namespace sculpt::hal
