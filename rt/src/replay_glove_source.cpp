#include "sculpt/rt/replay_glove_source.hpp"

#include <algorithm>

namespace sculpt::rt {

ReplayGloveSource::ReplayGloveSource(std::vector<hal::GloveSample> samples) : samples_(std::move(samples)) {
  std::stable_sort(samples_.begin(), samples_.end(), [](const hal::GloveSample& a, const hal::GloveSample& b) {
    return a.receive_time_ns < b.receive_time_ns;
  });
}

std::size_t ReplayGloveSource::poll(std::span<hal::GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && next_ < samples_.size() && samples_[next_].receive_time_ns <= now_ns_) {
    out[n++] = samples_[next_++];
  }
  counters_.samples += n;
  return n;
}

std::int64_t ReplayGloveSource::first_time_ns() const noexcept {
  return samples_.empty() ? 0 : samples_.front().receive_time_ns;
}

std::int64_t ReplayGloveSource::last_time_ns() const noexcept {
  return samples_.empty() ? 0 : samples_.back().receive_time_ns;
}

}  // namespace sculpt::rt
