// The allocation counter must see a real allocation and nothing else, or every "allocates
// nothing" test built on it proves nothing.
#include "support/allocation_counter.hpp"

// The replacement operator new/delete, compiled here because the test glob picks up only
// *_test.cpp files (see the comment at the top of that file).
#include "rt/allocation_counter.cpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>
#include <vector>

namespace sculpt::test {
namespace {

// Keeps the optimiser from removing a new/delete pair it can see through (allowed since C++14).
template <typename T>
void escape(T* p) {
  asm volatile("" : : "g"(p) : "memory");
}

TEST(AllocationCounter, CountsAVectorGrowing) {
  std::vector<int> v;
  AllocationCounter guard;
  for (int i = 0; i < 100; ++i) v.push_back(i);
  escape(v.data());
  // Geometric growth from empty: 1, 2, 4, ..., 128 is 8 allocations in libstdc++; at least one
  // whatever the growth factor.
  EXPECT_GE(guard.count(), 1u);
  EXPECT_LE(guard.count(), 100u);
}

TEST(AllocationCounter, DoesNotCountAPushBackIntoReservedStorage) {
  std::vector<int> v;
  v.reserve(100);
  AllocationCounter guard;
  for (int i = 0; i < 100; ++i) v.push_back(i);
  escape(v.data());
  EXPECT_EQ(guard.count(), 0u);
}

TEST(AllocationCounter, CountsEachFormOfNew) {
  AllocationCounter guard;
  auto* a = new int(1);
  escape(a);
  auto* b = new int[4];
  escape(b);
  auto* c = new (std::nothrow) double(2.0);
  escape(c);
  struct alignas(64) Wide {
    double x[8];
  };
  auto* d = new Wide();
  escape(d);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(d) % 64, 0u);
  EXPECT_EQ(guard.count(), 4u);
  delete a;
  delete[] b;
  delete c;
  delete d;
  EXPECT_EQ(guard.count(), 4u) << "frees are not allocations";
}

TEST(AllocationCounter, CountsNothingOutsideTheGuard) {
  std::uint64_t inside = 0;
  {
    AllocationCounter guard;
    auto p = std::make_unique<int>(3);
    escape(p.get());
    inside = guard.count();
  }
  EXPECT_EQ(inside, 1u);
  const std::uint64_t before = thread_allocations();
  auto q = std::make_unique<int>(4);
  escape(q.get());
  EXPECT_EQ(thread_allocations(), before) << "no guard alive: nothing is counted";
}

TEST(AllocationCounter, CountsOnlyTheGuardedThread) {
  AllocationCounter guard;
  std::uint64_t other_thread_count = 1;
  // The thread's own start-up allocation is made here and counted: measure after it.
  const std::uint64_t before_thread = guard.count();
  std::thread t([&other_thread_count] {
    auto p = std::make_unique<int>(5);
    escape(p.get());
    other_thread_count = thread_allocations();
  });
  const std::uint64_t after_spawn = guard.count();
  t.join();
  EXPECT_EQ(other_thread_count, 0u) << "the other thread has no guard";
  EXPECT_EQ(guard.count(), after_spawn) << "the other thread's allocation is not ours";
  EXPECT_GE(after_spawn, before_thread);
}

TEST(AllocationCounter, NestedGuardsBothCount) {
  AllocationCounter outer;
  {
    AllocationCounter inner;
    auto p = std::make_unique<int>(6);
    escape(p.get());
    EXPECT_EQ(inner.count(), 1u);
  }
  auto q = std::make_unique<int>(7);
  escape(q.get());
  EXPECT_EQ(outer.count(), 2u);
}

}  // namespace
}  // namespace sculpt::test
