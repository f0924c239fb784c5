#pragma once
// A glove source that plays recorded samples in virtual time, for deterministic re-runs.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/hal/glove_source.hpp"

namespace sculpt::rt {

/// Holds recorded samples (ascending receive time) and hands over, at each poll, those whose
/// receive time is not after the virtual clock set by the caller.
class ReplayGloveSource final : public hal::GloveSource {
 public:
  explicit ReplayGloveSource(std::vector<hal::GloveSample> samples);
  void start() override {}
  void stop() override {}
  std::size_t poll(std::span<hal::GloveSample> out) noexcept override;
  hal::SourceCounters counters() const noexcept override { return counters_; }
  hal::SourceState state() const noexcept override { return hal::SourceState::kConnected; }
  const char* name() const noexcept override { return "replay"; }

  void set_now(std::int64_t now_ns) noexcept { now_ns_ = now_ns; }
  bool finished() const noexcept { return next_ == samples_.size(); }
  std::int64_t first_time_ns() const noexcept;
  std::int64_t last_time_ns() const noexcept;

 private:
  std::vector<hal::GloveSample> samples_;
  std::size_t next_ = 0;
  std::int64_t now_ns_ = 0;
  hal::SourceCounters counters_;
};

}  // namespace sculpt::rt
