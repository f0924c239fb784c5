#pragma once
// A second core for the displacement loop: one thread started at set-up that waits for work,
// so that a frame hands it half of its points without creating a thread, taking a lock or
// allocating. The caller works on the other half and waits for it; the halves are disjoint, and
// every per-point result is the same whichever thread computes it, so the frame is bit for bit
// what one thread makes.

#include <atomic>
#include <cstdint>
#include <thread>

namespace sculpt::deform {

class FieldWorker {
 public:
  /// A task: `part` 0 runs on the caller, 1 on the worker; `context` is the caller's.
  using Task = void (*)(void* context, int part) noexcept;

  /// Starts the thread (set-up time: may throw std::system_error).
  FieldWorker();
  ~FieldWorker();
  FieldWorker(const FieldWorker&) = delete;
  FieldWorker& operator=(const FieldWorker&) = delete;

  /// Runs task(context, 1) on the worker and task(context, 0) here, and returns when both are
  /// done. No allocation, no lock: two atomics, and a futex wait where one side is early.
  /// One caller at a time.
  void run_both(Task task, void* context) noexcept;

  /// How many tasks the worker has run (for tests: the second core really took part).
  std::uint64_t tasks_run() const noexcept { return done_.load(std::memory_order_acquire); }

 private:
  void loop() noexcept;

  Task task_ = nullptr;
  void* context_ = nullptr;
  std::atomic<std::uint64_t> posted_{0};  // generation of the last task handed over
  std::atomic<std::uint64_t> done_{0};    // generation of the last task the worker finished
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace sculpt::deform
