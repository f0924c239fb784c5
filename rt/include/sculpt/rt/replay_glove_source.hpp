#pragma once
// A glove source that plays recorded samples in virtual time, for deterministic re-runs.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/hal/glove_source.hpp"

namespace sculpt::rt {

/// Glove samples as a log holds them, and which of the live loop's ticks took each.
struct SampleLog {
  std::vector<hal::GloveSample> samples;  ///< in the log's order
  /// Per sample, the tick of the live loop that took it, numbered in the log's order (the samples
  /// of one tick share a number, and numbers ascend); -1 where the log does not say (a log that
  /// is not a station's, a crash's last samples). Empty: -1 for every sample.
  std::vector<std::int64_t> taken;
};

/// Hands over, at each poll, the samples due at the virtual clock set by the caller (set_now,
/// once a tick). The live loop keeps only a hand's newest sample of those a tick takes, so a
/// re-run agrees with it only if its ticks take the same samples together: samples whose tick
/// the log names come a live tick's worth per tick, once the last of them has arrived (a tick
/// later than live when two live ticks' samples arrived within one period); the rest come by
/// receive time, every sample due.
class ReplayGloveSource final : public hal::GloveSource {
 public:
  explicit ReplayGloveSource(SampleLog log);
  void start() override {}
  void stop() override {}
  std::size_t poll(std::span<hal::GloveSample> out) noexcept override;
  hal::SourceCounters counters() const noexcept override { return counters_; }
  hal::SourceState state() const noexcept override { return hal::SourceState::kConnected; }
  const char* name() const noexcept override { return "replay"; }

  void set_now(std::int64_t now_ns) noexcept {
    now_ns_ = now_ns;
    took_a_tick_ = false;
  }
  bool finished() const noexcept { return next_ == samples_.size(); }
  /// The virtual time of the tick after the one at `now`: `period` later, or, across a gap in
  /// the samples, the last tick on the same grid before the next one is due, once no sample has
  /// come for `idle_ns` (longer than the glove's timeout: the loop has released the glove, and
  /// the ticks until the next sample change nothing but their count). A re-run then costs what
  /// its samples hold, not the time they span (a log edited to a sample years later).
  std::int64_t next_tick_ns(std::int64_t now, std::int64_t period, std::int64_t idle_ns) const noexcept;
  std::int64_t first_time_ns() const noexcept;
  /// When the last sample is due.
  std::int64_t last_time_ns() const noexcept { return last_due_ns_; }

 private:
  std::vector<hal::GloveSample> samples_;
  std::vector<std::int64_t> taken_;   // per sample, as SampleLog::taken (never empty)
  std::vector<std::int64_t> due_ns_;  // per sample: the newest receive time of its live tick's
  std::int64_t last_due_ns_ = 0;
  std::size_t next_ = 0;
  std::int64_t now_ns_ = 0;
  std::int64_t open_tick_ = -1;  // the live tick whose samples are being handed over
  bool took_a_tick_ = false;     // since set_now
  hal::SourceCounters counters_;
};

}  // namespace sculpt::rt
