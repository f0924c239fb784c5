#pragma once
// Bounded single-producer single-consumer queue: the one way data crosses between an I/O
// thread and the real-time loop. Wait-free on both sides, no allocation after construction.

#include <atomic>
#include <cstddef>
#include <memory>
#include <new>
#include <optional>
#include <type_traits>

namespace sculpt::base {

template <typename T>
class SpscQueue {
  static_assert(std::is_trivially_copyable_v<T>, "elements are copied by value across threads");

 public:
  /// Capacity is rounded up to a power of two (at least 2).
  explicit SpscQueue(std::size_t capacity) : mask_(round_up(capacity) - 1), slots_(new T[mask_ + 1]) {}

  /// Producer side. False when full (the caller counts the overflow).
  bool push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_cache_ > mask_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head - tail_cache_ > mask_) return false;
    }
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer side. False when empty.
  bool pop(T& out) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_cache_) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail == head_cache_) return false;
    }
    out = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Consumer side: nothing to pop now.
  bool empty() const noexcept { return tail_.load(std::memory_order_relaxed) == head_.load(std::memory_order_acquire); }

  std::size_t capacity() const noexcept { return mask_ + 1; }

 private:
  static std::size_t round_up(std::size_t n) {
    std::size_t c = 2;
    while (c < n) c <<= 1;
    return c;
  }

  const std::size_t mask_;
  std::unique_ptr<T[]> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::size_t tail_cache_ = 0;  // producer's copy of tail
  alignas(64) std::atomic<std::size_t> tail_{0};
  alignas(64) std::size_t head_cache_ = 0;  // consumer's copy of head
};

}  // namespace sculpt::base
