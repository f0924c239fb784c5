#include "sequence_tracker.hpp"

namespace sculpt::hal {

std::uint32_t SequenceTracker::observe(std::uint8_t hand, std::uint32_t sequence) noexcept {
  if (hand >= hands_.size()) return 0;
  Hand& h = hands_[hand];
  const bool first = !h.seen;
  // Unsigned subtraction is the distance forward modulo 2^32, so a wrap is an ordinary step.
  const std::uint32_t forward = sequence - h.last;
  h.seen = true;
  h.last = sequence;
  if (first || forward == 0 || forward >= 0x80000000u) return 0;
  const std::uint32_t missing = forward - 1;
  gaps_ += missing;
  return missing;
}

void SequenceTracker::reset() noexcept {
  hands_ = {};
  gaps_ = 0;
}

}  // namespace sculpt::hal
