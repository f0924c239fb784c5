#include "sculpt/deform/field_worker.hpp"

#include <chrono>

namespace sculpt::deform {

namespace {
// How long the worker spins for the next frame before it sleeps.
constexpr std::chrono::microseconds kSpin{200};
// How long the caller spins for the worker's last part before it sleeps: shorter, because a
// caller that spins while the worker waits for a core (the station's I/O and logger threads
// share it) only delays it. Measured with 100 us halves a 300 us gap apart (3,000 calls, three
// runs): median 139-149 us a call sleeping at once, 107-111 us with this spin.
constexpr std::chrono::microseconds kJoinSpin{50};

constexpr std::uint64_t kField = 0xffff;
constexpr std::uint64_t generation_of(std::uint64_t state) { return state >> 32; }
constexpr std::uint64_t parts_of(std::uint64_t state) { return (state >> 16) & kField; }
constexpr std::uint64_t next_of(std::uint64_t state) { return state & kField; }
}  // namespace

FieldWorker::FieldWorker() : thread_([this] { loop(); }) {}

FieldWorker::~FieldWorker() {
  stop_.store(true, std::memory_order_release);
  // A new generation with no parts: the worker wakes, sees the stop and claims nothing.
  state_.store((generation_ + 1) << 32, std::memory_order_release);
  state_.notify_one();
  thread_.join();
}

bool FieldWorker::claim(std::uint64_t generation, std::size_t& part) noexcept {
  std::uint64_t state = state_.load(std::memory_order_acquire);
  for (;;) {
    if (generation_of(state) != generation || next_of(state) >= parts_of(state)) return false;
    // Acquire: the task's inputs, written before it was posted, are visible to the claimer.
    if (state_.compare_exchange_weak(state, state + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      part = static_cast<std::size_t>(next_of(state));
      return true;
    }
  }
}

void FieldWorker::run_parts(Task task, void* context, std::size_t parts) noexcept {
  if (parts > kMaxParts) parts = kMaxParts;
  if (parts == 0) return;
  task_.store(task, std::memory_order_relaxed);
  context_.store(context, std::memory_order_relaxed);
  finished_.store(0, std::memory_order_relaxed);
  const std::uint64_t generation = ++generation_ & 0xffffffffu;
  // Release: the task, its context and everything the caller wrote before are visible to the
  // worker once it sees the new generation.
  state_.store(generation << 32 | static_cast<std::uint64_t>(parts) << 16, std::memory_order_release);
  state_.notify_one();
  std::size_t part = 0;
  while (claim(generation, part)) {
    task(context, part);
    finished_.fetch_add(1, std::memory_order_relaxed);  // this thread's own work needs no ordering
  }
  // Acquire: the worker's parts are visible here once it has counted them. Its last part
  // usually ends within microseconds of this thread's: spin for it before sleeping (a futex
  // wake-up costs tens of microseconds on a VM).
  const auto all = static_cast<std::uint32_t>(parts);
  std::uint32_t seen = finished_.load(std::memory_order_acquire);
  const auto spin_until = std::chrono::steady_clock::now() + kJoinSpin;
  while (seen != all && std::chrono::steady_clock::now() < spin_until) {
    __builtin_ia32_pause();
    seen = finished_.load(std::memory_order_acquire);
  }
  while (seen != all) {
    finished_.wait(seen, std::memory_order_acquire);
    seen = finished_.load(std::memory_order_acquire);
  }
}

void FieldWorker::loop() noexcept {
  std::uint64_t handled = 0;  // the last generation this thread took part in
  for (;;) {
    std::uint64_t state = state_.load(std::memory_order_acquire);
    // Frames come a tick apart while a finger presses: spin a little before sleeping, since a
    // futex wake-up costs tens of microseconds on a virtual machine.
    const auto spin_until = std::chrono::steady_clock::now() + kSpin;
    while (generation_of(state) == handled && std::chrono::steady_clock::now() < spin_until) {
      __builtin_ia32_pause();
      state = state_.load(std::memory_order_acquire);
    }
    if (generation_of(state) != handled) met_awake_.fetch_add(1, std::memory_order_relaxed);
    while (generation_of(state) == handled) {
      state_.wait(state, std::memory_order_acquire);
      state = state_.load(std::memory_order_acquire);
    }
    if (stop_.load(std::memory_order_acquire)) return;
    handled = generation_of(state);
    // Read before claiming: once a claim of this generation succeeds, the caller is still in
    // its run_parts() (a part of it is not done), so these are this task's.
    const Task task = task_.load(std::memory_order_relaxed);
    void* const context = context_.load(std::memory_order_relaxed);
    const auto all = static_cast<std::uint32_t>(parts_of(state));
    std::size_t part = 0;
    while (claim(handled, part)) {
      task(context, part);
      worker_parts_.fetch_add(1, std::memory_order_release);
      // Release: this part's results are visible to the caller once it sees the count.
      if (finished_.fetch_add(1, std::memory_order_acq_rel) + 1 == all) finished_.notify_one();
    }
  }
}

}  // namespace sculpt::deform
