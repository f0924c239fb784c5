#pragma once
// A second core for the displacement loop: one thread started at set-up that waits for work,
// so that a frame shares its points with it without creating a thread, taking a lock or
// allocating. A pass is cut into parts that the caller and the worker claim one at a time as
// each comes free; the parts are disjoint, and every per-point result is the same whichever
// thread computes it, so the frame is bit for bit what one thread makes.
//
// Why parts claimed rather than a half each: in the station the worker's core also runs the
// I/O and logger threads, and this VM's host may hold a virtual CPU for milliseconds. A half
// handed to a worker that was not running held the frame until it ran (a global 100k frame,
// 0.3-0.4 ms at the median, took up to 7.8 ms in the station on two threads, 1 ms on one). A part
// the worker has not begun when the caller comes free is the caller's: the wait is at most the
// part the worker is in.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

namespace sculpt::deform {

class FieldWorker {
 public:
  /// One part of a task: `part` in 0 .. parts - 1; `context` is the caller's.
  using Task = void (*)(void* context, std::size_t part) noexcept;

  /// The most parts a task may have.
  static constexpr std::size_t kMaxParts = 0xffff;

  /// Starts the thread (set-up time: may throw std::system_error).
  FieldWorker();
  ~FieldWorker();
  FieldWorker(const FieldWorker&) = delete;
  FieldWorker& operator=(const FieldWorker&) = delete;

  /// Runs task(context, k) once for every k in 0 .. parts - 1 (at most kMaxParts: more are not
  /// run), each on this thread or the worker, whichever claims it first, and returns when all
  /// are done. No allocation, no lock: atomics, and a futex wait where one side is early.
  /// One caller at a time.
  void run_parts(Task task, void* context, std::size_t parts) noexcept;

  /// How many parts the worker has run (for tests: the second core really took part).
  std::uint64_t parts_run() const noexcept { return worker_parts_.load(std::memory_order_acquire); }
  /// How many tasks found the worker still spinning after the one before, rather than asleep
  /// (a sleeping worker starts its first part 20-75 us after the post on these VMs).
  std::uint64_t tasks_met_awake() const noexcept { return met_awake_.load(std::memory_order_relaxed); }

 private:
  void loop() noexcept;
  // Claims the next part of the task of `generation` into `part`; false when none is left or
  // another task has been posted since.
  bool claim(std::uint64_t generation, std::size_t& part) noexcept;

  // The task being shared out, in one word so that a claim can never take a part of another
  // task: its generation (bits 32-63), its number of parts (16-31) and the next part unclaimed
  // (0-15).
  std::atomic<std::uint64_t> state_{0};
  std::atomic<Task> task_{nullptr};
  std::atomic<void*> context_{nullptr};
  std::atomic<std::uint32_t> finished_{0};  // parts of the current task done
  std::atomic<std::uint64_t> worker_parts_{0};
  std::atomic<std::uint64_t> met_awake_{0};
  std::uint64_t generation_ = 0;  // the caller's: the last task posted
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace sculpt::deform
