#pragma once
// Counts samples lost on the way from the glove, from the device's per-hand sequence numbers.

#include <array>
#include <cstdint>

#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// Per hand, remembers the last sequence number seen and counts the numbers skipped since.
/// Wrap-around aware (0xFFFFFFFF -> 0 is in order). A backwards jump (half the number space or
/// more, modulo 2^32) is taken as the device restarting its counter, e.g. after a reconnect,
/// and counts nothing; so does a repeated number. Not thread-safe; noexcept, no allocation.
class SequenceTracker {
 public:
  /// Records `sequence` for `hand` and returns how many numbers were skipped before it (0 for
  /// the first sample of a hand). Hands >= kHands are ignored (0).
  std::uint32_t observe(std::uint8_t hand, std::uint32_t sequence) noexcept;

  /// Total skipped numbers over all hands since construction or reset().
  std::uint64_t gaps() const noexcept { return gaps_; }

  /// Forgets every hand's last number and the total.
  void reset() noexcept;

 private:
  struct Hand {
    bool seen = false;
    std::uint32_t last = 0;
  };
  std::array<Hand, kHands> hands_{};
  std::uint64_t gaps_ = 0;
};

}  // namespace sculpt::hal
