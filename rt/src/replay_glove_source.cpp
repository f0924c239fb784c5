#include "sculpt/rt/replay_glove_source.hpp"

#include <algorithm>

namespace sculpt::rt {

ReplayGloveSource::ReplayGloveSource(SampleLog log) : samples_(std::move(log.samples)), taken_(std::move(log.taken)) {
  if (taken_.size() != samples_.size()) taken_.assign(samples_.size(), -1);
  // The samples whose tick is unknown (all of a log that is not a station's, or a crash's last
  // ones after the named ticks) go by receive time.
  const auto unknown = static_cast<std::ptrdiff_t>(
      std::find_if(taken_.rbegin(), taken_.rend(), [](std::int64_t t) { return t >= 0; }) - taken_.rbegin());
  const auto tail = samples_.end() - unknown;
  std::stable_sort(tail, samples_.end(), [](const hal::GloveSample& a, const hal::GloveSample& b) {
    return a.receive_time_ns < b.receive_time_ns;
  });
  due_ns_.resize(samples_.size());
  for (std::size_t begin = 0; begin < samples_.size();) {
    std::size_t end = begin + 1;
    std::int64_t due = samples_[begin].receive_time_ns;
    if (taken_[begin] >= 0) {
      for (; end < samples_.size() && taken_[end] == taken_[begin]; ++end) {
        due = std::max(due, samples_[end].receive_time_ns);
      }
    }
    std::fill(due_ns_.begin() + static_cast<std::ptrdiff_t>(begin), due_ns_.begin() + static_cast<std::ptrdiff_t>(end),
              due);
    last_due_ns_ = std::max(last_due_ns_, due);
    begin = end;
  }
}

std::size_t ReplayGloveSource::poll(std::span<hal::GloveSample> out) noexcept {
  std::size_t n = 0;
  while (n < out.size() && next_ < samples_.size()) {
    const std::int64_t tick = taken_[next_];
    if (tick < 0 || tick != open_tick_) {
      if (took_a_tick_ || due_ns_[next_] > now_ns_) break;  // one live tick's samples a tick
      if (tick >= 0) {
        open_tick_ = tick;
        took_a_tick_ = true;
      }
    }
    out[n++] = samples_[next_++];
  }
  counters_.samples += n;
  return n;
}

std::int64_t ReplayGloveSource::next_tick_ns(std::int64_t now, std::int64_t period,
                                             std::int64_t idle_ns) const noexcept {
  const std::int64_t next = now + period;
  if (next_ == 0 || finished() || period <= 0) return next;
  const std::int64_t quiet_since = samples_[next_ - 1].receive_time_ns;
  const std::int64_t due = due_ns_[next_];
  if (next - quiet_since < idle_ns || due <= next) return next;
  return next + (due - next - 1) / period * period;  // the grid's last tick before `due`
}

std::int64_t ReplayGloveSource::first_time_ns() const noexcept {
  return samples_.empty() ? 0 : samples_.front().receive_time_ns;
}

}  // namespace sculpt::rt
