// Replacement global operator new/delete for the rt_tests binary, counting allocations on a
// thread while an AllocationCounter is alive there (tests/support/allocation_counter.hpp).
//
// Built into rt_tests through tests/rt/allocation_counter_test.cpp, which includes this file:
// the test folders glob only *_test.cpp, and a replacement operator new must be defined in
// exactly one translation unit (it may not be inline).
// These replacements pair malloc with free on purpose (operator new here is malloc). GCC 12 at
// -O1 reports -Wmismatched-new-delete on them once it inlines the pair; that is a false positive
// for replacement allocation functions.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include "support/allocation_counter.hpp"

#include <cstdlib>
#include <new>

namespace {

// Constant-initialised thread_locals: reading them needs no initialisation guard and so can
// never allocate, even from inside operator new.
constinit thread_local std::uint64_t t_allocations = 0;
constinit thread_local int t_depth = 0;

void note_allocation() noexcept {
  if (t_depth > 0) ++t_allocations;
}

void* allocate(std::size_t size) {
  note_allocation();
  // malloc(0) may return null; operator new must not.
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

void* allocate_aligned(std::size_t size, std::align_val_t alignment) {
  note_allocation();
  const std::size_t a = static_cast<std::size_t>(alignment);
  // aligned_alloc wants a size that is a multiple of the alignment.
  const std::size_t rounded = ((size == 0 ? 1 : size) + a - 1) / a * a;
  if (void* p = std::aligned_alloc(a, rounded)) return p;
  throw std::bad_alloc();
}

}  // namespace

namespace sculpt::test {

std::uint64_t thread_allocations() noexcept { return t_allocations; }

namespace detail {
void begin_counting() noexcept { ++t_depth; }
void end_counting() noexcept { --t_depth; }
}  // namespace detail

}  // namespace sculpt::test

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t alignment) { return allocate_aligned(size, alignment); }
void* operator new[](std::size_t size, std::align_val_t alignment) { return allocate_aligned(size, alignment); }
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(size, alignment);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  try {
    return allocate_aligned(size, alignment);
  } catch (...) {
    return nullptr;
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
