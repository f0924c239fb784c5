#include "sim_glove_source.hpp"

#include "sculpt/base/clock.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>

namespace sculpt::hal {
namespace {

// The thread wakes at least this often while waiting, so stop() never waits on a long gap
// between samples.
constexpr std::int64_t kMaxSleepNs = 20'000'000;

}  // namespace

SimGloveSource::SimGloveSource(const SimConfig& config, std::size_t queue_capacity)
    : script_(config),
      latency_ns_(static_cast<std::int64_t>(std::llround(config.latency_ms * 1e6))),
      queue_(queue_capacity) {}

SimGloveSource::~SimGloveSource() { stop(); }

void SimGloveSource::start() {
  if (thread_.joinable()) {
    if (!finished()) return;  // still playing
    thread_.join();           // played to the end: start over
  }
  script_.reset();
  stop_requested_.store(false, std::memory_order_relaxed);
  finished_.store(false, std::memory_order_relaxed);
  start_ns_ = base::monotonic_now_ns();
  state_.store(SourceState::kConnected, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void SimGloveSource::stop() {
  stop_requested_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  state_.store(SourceState::kStopped, std::memory_order_release);
}

void SimGloveSource::run() noexcept {
  // The script's counters start at 0, so even a dropout before a hand's first delivered
  // sample is a gap.
  std::array<std::uint32_t, kHands> next_sequence{};
  GloveSample sample;
  while (!stop_requested_.load(std::memory_order_acquire)) {
    if (!script_.next(sample)) {
      finished_.store(true, std::memory_order_release);
      return;
    }
    const std::int64_t due = start_ns_ + static_cast<std::int64_t>(sample.device_time_us) * 1000 + latency_ns_;
    for (std::int64_t now = base::monotonic_now_ns(); now < due; now = base::monotonic_now_ns()) {
      if (stop_requested_.load(std::memory_order_acquire)) return;
      base::sleep_until_ns(std::min(due, now + kMaxSleepNs));
    }
    sample.receive_time_ns = base::monotonic_now_ns();
    const std::size_t h = sample.hand;
    if (sample.sequence != next_sequence[h])
      counters_.sequence_gaps.fetch_add(sample.sequence - next_sequence[h], std::memory_order_relaxed);
    next_sequence[h] = sample.sequence + 1;
    if (queue_.push(sample))
      counters_.samples.fetch_add(1, std::memory_order_relaxed);
    else
      counters_.overflows.fetch_add(1, std::memory_order_relaxed);
  }
}

std::size_t SimGloveSource::poll(std::span<GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && queue_.pop(out[n])) ++n;
  return n;
}

SourceCounters SimGloveSource::counters() const noexcept { return counters_.snapshot(); }

}  // namespace sculpt::hal
