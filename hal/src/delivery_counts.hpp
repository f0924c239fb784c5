#pragma once
// What a haptic sink put on its link: every command, and per hand those that carried a contact
// (a finger's bit set in the active mask), the forces a hand could feel. A run summary's rate
// over the whole run counts idle and release frames too; the in-contact count tells whether the
// hand got a force every tick while it pressed. Counted by the sink's I/O thread, read by
// anyone (relaxed: counts, not synchronisation).

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "sculpt/hal/haptic_sink.hpp"

namespace sculpt::hal {

class DeliveryCounts {
 public:
  /// One command reached the link.
  void count(const HapticCommand& command) noexcept {
    total_.fetch_add(1, std::memory_order_relaxed);
    if (command.active_mask != 0 && command.hand < kHands)
      in_contact_[command.hand].fetch_add(1, std::memory_order_relaxed);
  }
  std::uint64_t total() const noexcept { return total_.load(std::memory_order_relaxed); }
  /// 0 for a hand that does not exist.
  std::uint64_t in_contact(std::size_t hand) const noexcept {
    return hand < kHands ? in_contact_[hand].load(std::memory_order_relaxed) : 0;
  }

 private:
  std::atomic<std::uint64_t> total_{0};
  std::array<std::atomic<std::uint64_t>, kHands> in_contact_{};
};

}  // namespace sculpt::hal
