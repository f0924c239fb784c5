#pragma once
// Proves that code allocates nothing: while an AllocationCounter lives, every global
// operator new on *its* thread is counted. The replacement operators are defined once, in
// tests/rt/allocation_counter.cpp; other threads (gtest, a helper setting a stop flag) are
// never counted, so a test measures exactly the thread it guards.

#include <cstdint>

namespace sculpt::test {

/// Allocations made by the calling thread while at least one AllocationCounter is alive on it.
std::uint64_t thread_allocations() noexcept;

namespace detail {
void begin_counting() noexcept;
void end_counting() noexcept;
}  // namespace detail

/// Scope guard: `AllocationCounter guard; work(); EXPECT_EQ(guard.count(), 0u);`.
/// Counts calls of every form of operator new / new[] (plain, nothrow, aligned) on this thread.
class AllocationCounter {
 public:
  AllocationCounter() noexcept : start_((detail::begin_counting(), thread_allocations())) {}
  ~AllocationCounter() { detail::end_counting(); }
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;

  /// Allocations on this thread since the guard was made.
  std::uint64_t count() const noexcept { return thread_allocations() - start_; }

 private:
  std::uint64_t start_;
};

}  // namespace sculpt::test
