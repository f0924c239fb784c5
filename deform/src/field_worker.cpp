#include "sculpt/deform/field_worker.hpp"

#include <chrono>

namespace sculpt::deform {

namespace {
// How long the worker spins for the next frame before it sleeps.
constexpr std::chrono::microseconds kSpin{200};
// How long the caller spins for the worker's half before it sleeps: shorter, because a caller
// that spins while the worker waits for a core (the station's I/O and logger threads share it)
// only delays it. Measured with 100 us halves a 300 us gap apart (3,000 calls, three runs):
// median 139-149 us a call sleeping at once, 107-111 us with this spin.
constexpr std::chrono::microseconds kJoinSpin{50};
}  // namespace

FieldWorker::FieldWorker() : thread_([this] { loop(); }) {}

FieldWorker::~FieldWorker() {
  stop_.store(true, std::memory_order_release);
  posted_.fetch_add(1, std::memory_order_acq_rel);
  posted_.notify_one();
  thread_.join();
}

void FieldWorker::run_both(Task task, void* context) noexcept {
  task_ = task;
  context_ = context;
  // Release: the task and its context (and everything the caller wrote before) are visible to
  // the worker once it sees the new generation.
  const std::uint64_t generation = posted_.fetch_add(1, std::memory_order_acq_rel) + 1;
  posted_.notify_one();
  task(context, 0);
  // Acquire: the worker's half of the results is visible here once it reports the generation.
  // The two halves are the same size, so the worker's usually ends within microseconds of this
  // one: spin for it before sleeping (a futex wake-up costs tens of microseconds on a VM).
  std::uint64_t seen = done_.load(std::memory_order_acquire);
  const auto spin_until = std::chrono::steady_clock::now() + kJoinSpin;
  while (seen != generation && std::chrono::steady_clock::now() < spin_until) {
    __builtin_ia32_pause();
    seen = done_.load(std::memory_order_acquire);
  }
  while (seen != generation) {
    done_.wait(seen, std::memory_order_acquire);
    seen = done_.load(std::memory_order_acquire);
  }
}

void FieldWorker::loop() noexcept {
  std::uint64_t handled = 0;
  for (;;) {
    std::uint64_t generation = posted_.load(std::memory_order_acquire);
    // Frames come a tick apart while a finger presses: spin a little before sleeping, since a
    // futex wake-up costs tens of microseconds on a virtual machine.
    const auto spin_until = std::chrono::steady_clock::now() + kSpin;
    while (generation == handled && std::chrono::steady_clock::now() < spin_until) {
      __builtin_ia32_pause();
      generation = posted_.load(std::memory_order_acquire);
    }
    while (generation == handled) {
      posted_.wait(generation, std::memory_order_acquire);
      generation = posted_.load(std::memory_order_acquire);
    }
    if (stop_.load(std::memory_order_acquire)) return;
    task_(context_, 1);
    handled = generation;
    done_.store(generation, std::memory_order_release);
    done_.notify_one();
  }
}

}  // namespace sculpt::deform
