#include "sculpt/logging/taken_ticks.hpp"

#include <algorithm>

#include "sculpt/logging/channels.hpp"

namespace sculpt::logging {

void TakenTicks::sample() { taken_.push_back(next_tick_); }

void TakenTicks::event(std::string_view channel) {
  // Not the session header (before every tick) nor a foreign channel (no tick of ours logs it).
  if (channel == kFingertipChannel || channel == kCollisionChannel || channel == kHapticChannel ||
      channel == kTickChannel) {
    end_run();
  }
}

void TakenTicks::damage() { end_run(); }

void TakenTicks::end_run() {
  if (ended_ == taken_.size()) return;
  ended_ = taken_.size();
  ++next_tick_;
}

std::vector<std::int64_t> TakenTicks::finish() const {
  std::vector<std::int64_t> out = taken_;
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(ended_), out.end(), -1);
  return out;
}

}  // namespace sculpt::logging
