// The fixed-rate loop on the real clock: overruns counted and skipped on the original phase,
// the stop flag honoured within a period, no allocation on the tick path, and the rate it
// achieves here. Shared, noisy machine: timing is asserted only against gross failure, and
// the exact counts are checked against the deadlines the ticks saw (an independent record).
// Also the real-time set-up, which must warn rather than fail.
#include "sculpt/rt/fixed_rate_loop.hpp"

#include "sculpt/rt/dead_band.hpp"
#include "sculpt/rt/one_euro_filter.hpp"
#include "sculpt/rt/realtime_setup.hpp"
#include "sculpt/rt/similarity_transform.hpp"
#include "support/allocation_counter.hpp"
#include "support/nanoseconds.hpp"

#include <gtest/gtest.h>

#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

namespace sculpt::rt {
namespace {

using test::kMs;

TEST(FixedRateLoop, AcceptsFiftyToTwoThousandHertz) {
  EXPECT_THROW(FixedRateLoop(49.9), std::invalid_argument);
  EXPECT_THROW(FixedRateLoop(2000.1), std::invalid_argument);
  EXPECT_THROW(FixedRateLoop(std::nan("")), std::invalid_argument);
  EXPECT_EQ(FixedRateLoop(50.0).period_ns(), 20 * kMs);
  EXPECT_EQ(FixedRateLoop(2000.0).period_ns(), kMs / 2);
  EXPECT_EQ(FixedRateLoop(1000.0).period_ns(), kMs);
  EXPECT_EQ(FixedRateLoop(120.0).period_ns(), 8'333'333);
}

TEST(FixedRateLoop, AStopFlagAlreadySetRunsNoTick) {
  FixedRateLoop loop(100.0);
  std::atomic<bool> stop{true};
  int calls = 0;
  loop.run([&](std::uint64_t, std::int64_t) noexcept { ++calls; }, stop);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(loop.stats().ticks, 0u);
  EXPECT_EQ(loop.achieved_rate(), 0.0);
}

// What the ticks saw, recorded without allocating.
struct Trace {
  static constexpr std::size_t kCapacity = 4096;
  std::array<std::int64_t, kCapacity> deadline{}, woke{}, ended{};
  std::size_t size = 0;
};

struct SlowTickRun {
  LoopStats stats;
  Trace trace;
};

// 100 Hz; tick 3 holds the thread until 35 ms after its own deadline (an absolute sleep, so
// the hold does not depend on how late tick 3 woke); stops after tick 8.
SlowTickRun run_with_slow_tick() {
  FixedRateLoop loop(100.0);
  std::atomic<bool> stop{false};
  SlowTickRun r;
  loop.run(
      [&](std::uint64_t k, std::int64_t deadline) noexcept {
        r.trace.deadline[k] = deadline;
        r.trace.woke[k] = monotonic_now_ns();
        if (k == 3) sleep_until_ns(deadline + 35 * kMs);
        r.trace.ended[k] = monotonic_now_ns();
        r.trace.size = k + 1;
        if (k == 8) stop.store(true);
      },
      stop);
  r.stats = loop.stats();
  return r;
}

TEST(FixedRateLoop, ASlowTickIsOneOverrunWhosePeriodsAreSkippedOnPhase) {
  const std::int64_t period = 10 * kMs;
  // Tick 3 ends 35 ms after its deadline D3 plus the wake-up latency of its sleep (epsilon):
  // D4, D5 and D6 have passed, D7 has not, so 3 periods are missed. A wake-up later than
  // 5 ms (a loaded machine) also passes D7: 4. Any other tick can overrun too when the
  // scheduler takes the core away for a period; so the counts are checked against the
  // deadlines actually seen on every attempt, and the exact "1 overrun" on a clean attempt.
  bool clean = false;
  for (int attempt = 0; attempt < 5 && !clean; ++attempt) {
    const SlowTickRun r = run_with_slow_tick();
    const Trace& t = r.trace;
    ASSERT_EQ(t.size, 9u);
    ASSERT_EQ(r.stats.ticks, 9u);
    std::uint64_t gaps_over_one = 0, skipped = 0;
    for (std::size_t k = 0; k < t.size; ++k) {
      // Absolute phase: every deadline is the first plus whole periods, and no wake is early.
      EXPECT_EQ((t.deadline[k] - t.deadline[0]) % period, 0) << "tick " << k;
      EXPECT_GE(t.woke[k], t.deadline[k]) << "tick " << k;
      if (k == 0) continue;
      const std::int64_t periods = (t.deadline[k] - t.deadline[k - 1]) / period;
      ASSERT_GE(periods, 1) << "two ticks on one deadline at tick " << k;
      if (periods > 1) ++gaps_over_one;
      skipped += static_cast<std::uint64_t>(periods - 1);
      // No catch-up burst: a tick's deadline is after the previous tick ended.
      EXPECT_GT(t.deadline[k], t.ended[k - 1]) << "tick " << k;
    }
    EXPECT_EQ(r.stats.overruns, gaps_over_one);
    EXPECT_EQ(r.stats.missed_periods, skipped);
    const std::int64_t after_slow = (t.deadline[4] - t.deadline[3]) / period - 1;
    EXPECT_GE(after_slow, 3);
    EXPECT_LE(after_slow, 4);
    EXPECT_EQ(r.stats.tick_time.count(), 9u);
    // The loop's own measure of tick 3 spans at least what the tick saw of itself.
    EXPECT_GE(r.stats.tick_time.max(), t.ended[3] - t.woke[3]);
    if (gaps_over_one == 1) {
      clean = true;
      EXPECT_EQ(r.stats.overruns, 1u);
      EXPECT_GE(r.stats.missed_periods, 3u);
      EXPECT_LE(r.stats.missed_periods, 4u);
      std::printf("slow tick: %llu overrun, %llu missed periods, tick 4 at D3 + %lld ms\n",
                  static_cast<unsigned long long>(r.stats.overruns),
                  static_cast<unsigned long long>(r.stats.missed_periods),
                  static_cast<long long>((t.deadline[4] - t.deadline[3]) / kMs));
    }
  }
  EXPECT_TRUE(clean) << "5 attempts, each with an overrun besides tick 3's: the machine is overloaded";
}

TEST(FixedRateLoop, FiveSecondsAtOneKilohertz) {  // the issue asks for the rate over 5 s
  FixedRateLoop loop(1000.0);
  std::atomic<bool> stop{false};
  std::uint64_t calls = 0;
  std::thread stopper([&stop] {
    std::this_thread::sleep_for(std::chrono::seconds(5));
    stop.store(true);
  });
  // On its own thread with 1 ns timer slack, as the station runs it without SCHED_FIFO.
  std::vector<std::string> warnings;
  std::thread runner([&] {
    RealtimeOptions o;
    o.tight_timer_slack = true;
    warnings = apply_realtime(o);
    loop.run([&](std::uint64_t, std::int64_t) noexcept { ++calls; }, stop);
  });
  runner.join();
  stopper.join();
  EXPECT_TRUE(warnings.empty());
  const LoopStats& s = loop.stats();
  const double rate = loop.achieved_rate();
  std::printf(
      "1 kHz for 5 s (timer slack 1 ns): achieved %.1f Hz, %llu ticks, %llu overruns, %llu missed "
      "periods\n"
      "  wake-up lateness: median %.1f us, p99 %.1f us, max %.1f us, mean %.1f us\n"
      "  tick time:        median %.2f us, p99 %.2f us, max %.2f us\n",
      rate, static_cast<unsigned long long>(s.ticks), static_cast<unsigned long long>(s.overruns),
      static_cast<unsigned long long>(s.missed_periods), s.wake_jitter.median() / 1e3, s.wake_jitter.p99() / 1e3,
      s.wake_jitter.max() / 1e3, s.wake_jitter.mean() / 1e3, s.tick_time.median() / 1e3, s.tick_time.p99() / 1e3,
      s.tick_time.max() / 1e3);
  RecordProperty("achieved_rate_hz", std::to_string(rate));
  EXPECT_EQ(calls, s.ticks);
  EXPECT_GT(rate, 500.0) << "gross failure only: the machine is shared";
  EXPECT_LT(rate, 1000.0 * 1.01) << "the loop never ticks faster than its rate";
  // Every tick and every skipped period used up one deadline, and every deadline used up had
  // passed before the loop ended: an exact bound, whatever the load.
  const auto elapsed_periods = static_cast<std::uint64_t>((s.ended_ns - s.started_ns) / loop.period_ns());
  EXPECT_LE(s.ticks + s.missed_periods, elapsed_periods);
  EXPECT_EQ(s.wake_jitter.count(), s.ticks);
  EXPECT_GE(s.wake_jitter.min(), 0) << "clock_nanosleep(TIMER_ABSTIME) never wakes early";
}

TEST(FixedRateLoop, StopsWithinOnePeriodOfTheFlag) {
  FixedRateLoop loop(50.0);  // 20 ms: long against scheduling noise
  const std::int64_t period = loop.period_ns();
  {
    // Set by the tick itself: that tick is the last; run() returns without sleeping again.
    std::atomic<bool> stop{false};
    std::int64_t set_at = 0;
    loop.run(
        [&](std::uint64_t k, std::int64_t) noexcept {
          if (k == 4) {
            stop.store(true);
            set_at = monotonic_now_ns();
          }
        },
        stop);
    EXPECT_EQ(loop.stats().ticks, 5u);
    EXPECT_LT(loop.stats().ended_ns - set_at, period);
  }
  {
    // Set from another thread while the loop sleeps: it wakes at the next deadline, sees the
    // flag and returns without ticking.
    std::atomic<bool> stop{false};
    std::array<std::int64_t, 64> tick_start{};
    std::atomic<std::uint64_t> ticks_seen{0};
    std::int64_t set_at = 0;
    std::thread stopper([&] {
      while (ticks_seen.load() < 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      std::this_thread::sleep_for(std::chrono::milliseconds(7));  // mid-period
      set_at = monotonic_now_ns();
      stop.store(true);
    });
    loop.run(
        [&](std::uint64_t k, std::int64_t) noexcept {
          tick_start[k % tick_start.size()] = monotonic_now_ns();
          ticks_seen.fetch_add(1);
        },
        stop);
    stopper.join();
    const std::int64_t stopped_after = loop.stats().ended_ns - set_at;
    std::printf("stop flag to return: %.2f ms (period %.0f ms)\n", stopped_after / 1e6, period / 1e6);
    // Gross bound: one period plus generous scheduling slack.
    EXPECT_LT(stopped_after, period + 50 * kMs);
    // At most one tick can start after the flag was set: one that had passed its check just
    // before (a narrow race); normally none.
    ASSERT_LE(loop.stats().ticks, tick_start.size());
    int after_flag = 0;
    for (std::size_t k = 0; k < loop.stats().ticks; ++k) after_flag += tick_start[k] > set_at;
    EXPECT_LE(after_flag, 1);
  }
}

TEST(FixedRateLoop, TheTicksCpuTimeLeavesOutWhatTheThreadDidNotRun) {
  // Even ticks sleep 3 ms (wall time, no CPU), odd ones spin until their thread has run 2 ms.
  // The wall-time histogram sees both; the CPU-time one sees only the spin. A preempted tick is
  // the sleeping one's case, seen from the loop.
  FixedRateLoop loop(100.0);  // 10 ms: room for either
  std::atomic<bool> stop{false};
  loop.run(
      [&](std::uint64_t k, std::int64_t) noexcept {
        if (k % 2 == 0) {
          sleep_until_ns(monotonic_now_ns() + 3 * kMs);
        } else {
          const std::int64_t start = thread_cpu_now_ns();
          while (thread_cpu_now_ns() - start < 2 * kMs) {
          }
        }
        if (k == 5) stop.store(true);
      },
      stop);
  const LoopStats& s = loop.stats();
  ASSERT_EQ(s.ticks, 6u);
  ASSERT_EQ(s.tick_cpu_time.count(), 6u);
  EXPECT_GE(s.tick_time.min(), 2 * kMs);      // every tick took at least 2 ms of wall time
  EXPECT_GE(s.tick_cpu_time.max(), 2 * kMs);  // the spinning ones used it
  EXPECT_LT(s.tick_cpu_time.min(), kMs);      // the sleeping ones did not
  EXPECT_LE(s.tick_cpu_time.max(), s.tick_time.max());
}

// The per-tick path of the station as far as rt has it: filter, dead band, registration, the
// loop's own accounting. After a warm-up run, nothing on this thread allocates.
TEST(FixedRateLoop, TheLoopAndTickPathAllocateNothingAfterWarmUp) {
  FixedRateLoop loop(2000.0);
  OneEuroFilter3 filter({1.0, 0.1, 1.0}, 2000.0);
  DeadBand band(1e-3);
  const SimilarityTransform to_model =
      SimilarityTransform::from_scale_rotation_translation(2.0, AxisAngle{{0, 1, 0}, 0.3}, {0.1, 0.2, 0.3});
  Trace trace;
  std::uint64_t accepted = 0;
  std::uint64_t stop_after = 10;
  std::atomic<bool> stop{false};
  auto tick = [&](std::uint64_t k, std::int64_t deadline) noexcept {
    const double t = static_cast<double>(deadline) * 1e-9;
    const std::array<double, 3> raw{std::sin(t), std::cos(t), 0.01 * static_cast<double>(k % 7)};
    if (band.offer(filter.filter(raw, t))) ++accepted;
    const auto p = to_model.apply(band.current());
    trace.deadline[k % Trace::kCapacity] = static_cast<std::int64_t>(p[0] * 1e6);
    if (k + 1 >= stop_after) stop.store(true);
  };
  loop.run(tick, stop);  // warm-up: first-touch of the code and stacks
  stop.store(false);
  stop_after = 400;
  {
    test::AllocationCounter guard;
    loop.run(tick, stop);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_EQ(loop.stats().ticks, 400u);
  EXPECT_GT(accepted, 0u);
}

TEST(RealtimeSetup, AskingForNothingGrantsNothingAndWarnsNothing) {
  EXPECT_TRUE(apply_realtime(RealtimeOptions{}).empty());
}

TEST(RealtimeSetup, RefusalsAreWarningsNotExceptions) {
  // On its own thread, so the test runner's scheduling and affinity are not changed.
  std::vector<std::string> warnings;
  std::thread t([&warnings] {
    RealtimeOptions o;
    o.fifo = true;
    o.priority = 10;
    o.cpu = 0;
    EXPECT_NO_THROW(warnings = apply_realtime(o));
  });
  t.join();
  for (const std::string& w : warnings) {
    std::printf("warning: %s\n", w.c_str());
    EXPECT_EQ(w.rfind("realtime: ", 0), 0u) << w;
  }
  EXPECT_LE(warnings.size(), 2u);

  // Timer slack needs no privilege: granted, and visible in /proc for that thread only.
  std::vector<std::string> slack_warnings;
  long slack_after = 0;
  std::thread v([&] {
    RealtimeOptions o;
    o.tight_timer_slack = true;
    slack_warnings = apply_realtime(o);
    slack_after = prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0);
  });
  v.join();
  EXPECT_TRUE(slack_warnings.empty());
  EXPECT_EQ(slack_after, 1);
  EXPECT_NE(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0), 1) << "the test runner's own thread is untouched";

  // A CPU this machine does not have: refused by the kernel (EINVAL), reported, not thrown.
  std::vector<std::string> missing_cpu;
  std::thread u([&missing_cpu] {
    RealtimeOptions o;
    o.cpu = CPU_SETSIZE - 1;
    EXPECT_NO_THROW(missing_cpu = apply_realtime(o));
  });
  u.join();
  ASSERT_EQ(missing_cpu.size(), 1u);
  EXPECT_NE(missing_cpu[0].find("CPU " + std::to_string(CPU_SETSIZE - 1)), std::string::npos) << missing_cpu[0];
}

TEST(RealtimeSetup, LockingMemoryWarnsOrSucceedsInAChildProcess) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "mlockall would try to lock AddressSanitizer's shadow memory";
#else
  // In a child, so the test runner's memory is never locked.
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    int code = 0;
    try {
      RealtimeOptions o;
      o.lock_memory = true;
      code = static_cast<int>(apply_realtime(o).size());  // 0 granted, 1 refused
    } catch (...) {
      code = 99;
    }
    _exit(code);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_LE(WEXITSTATUS(status), 1) << "apply_realtime threw";
  std::printf("mlockall in a child: %s\n", WEXITSTATUS(status) == 0 ? "granted" : "refused (warning)");
#endif
}

TEST(RealtimeSetup, ImpossibleOptionsAreErrors) {
  RealtimeOptions o;
  o.fifo = true;
  o.priority = 0;
  EXPECT_THROW(apply_realtime(o), std::invalid_argument);
  o.priority = 100;
  EXPECT_THROW(apply_realtime(o), std::invalid_argument);
  RealtimeOptions c;
  c.cpu = -2;
  EXPECT_THROW(apply_realtime(c), std::invalid_argument);
  c.cpu = CPU_SETSIZE;
  EXPECT_THROW(apply_realtime(c), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::rt

namespace sculpt::rt {
namespace {

// "require" refuses exactly the refusals a real-time station cannot run with.
TEST(RealtimeSetup, RequireRefusesOnlySchedFifoAndMemoryLockRefusals) {
  EXPECT_EQ(required_refusal({}), "");
  EXPECT_EQ(required_refusal({"realtime: timer slack 1 ns refused: EPERM"}), "");
  EXPECT_EQ(required_refusal({"realtime: pinning to CPU 7 refused: EINVAL"}), "");
  const std::string fifo = "realtime: SCHED_FIFO priority 80 refused: Operation not permitted";
  EXPECT_EQ(required_refusal({"realtime: pinning to CPU 7 refused: EINVAL", fifo}), fifo);
  const std::string lock = "realtime: mlockall refused: Cannot allocate memory";
  EXPECT_EQ(required_refusal({lock}), lock);
}

}  // namespace
}  // namespace sculpt::rt
