// The second core: a persistent worker shares the parts of a large displacement pass with the
// caller. The result must be bit for bit what one thread makes (every per-point value is
// computed by the same code from the same inputs, and the extremes reduce exactly), the worker
// must really run on another thread, the caller must take the parts the worker has not begun,
// the undo journal of a split pass must restore every byte, and a deformer with two threads
// must sculpt a stroke to exactly the bytes one thread makes.

#include "sculpt/deform/field_worker.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/generators.hpp"
#include "support/eventually.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

using test::same_bytes;

// A part waits (up to a deadline, polling without sleeping: the other thread is microseconds
// away) until `flag` reaches `value`; false when it never did.
bool wait_for(const std::atomic<int>& flag, int value) {
  return test::eventually([&] { return flag.load() >= value; }, std::chrono::seconds(10), std::chrono::milliseconds(0));
}

// Two parts that each wait until both have begun: neither thread can run both, so each runs
// one, and the call returns only once both are done.
TEST(FieldWorker, RunsThePartsOnBothThreadsAndWaitsForThem) {
  FieldWorker worker;
  struct Seen {
    std::atomic<int> begun{0};
    std::atomic<bool> timed_out{false};
    std::thread::id id[2];
    int calls[2] = {0, 0};
  } seen;
  for (int round = 0; round < 1000; ++round) {
    seen.begun = 0;
    worker.run_parts(
        [](void* context, std::size_t part) noexcept {
          Seen& s = *static_cast<Seen*>(context);
          s.id[part] = std::this_thread::get_id();
          ++s.calls[part];
          ++s.begun;
          if (!wait_for(s.begun, 2)) s.timed_out = true;
        },
        &seen, 2);
    ASSERT_FALSE(seen.timed_out) << "one thread ran both parts, or the worker never came";
    // Returned only once both parts ran: the counts never lag.
    ASSERT_EQ(seen.calls[0], round + 1);
    ASSERT_EQ(seen.calls[1], round + 1);
    ASSERT_NE(seen.id[0], seen.id[1]);
  }
  EXPECT_EQ(worker.parts_run(), 1000u);
}

// The count of tasks that found the worker awake: one posted long after the last finds it
// asleep (it spins 200 us, then sleeps), and so does every task after a pause. That back-to-back
// tasks find it spinning is timing (on a loaded machine none did, the worker off its core), so
// it is shown by deform_bench's worker_awake (0.96 at 100k), not asserted here.
TEST(FieldWorker, CountsTheTasksThatFoundItAwake) {
  FieldWorker worker;
  std::atomic<int> begun{0};
  const auto both = [&] {
    begun = 0;
    worker.run_parts(
        [](void* context, std::size_t) noexcept {
          auto& b = *static_cast<std::atomic<int>*>(context);
          ++b;
          wait_for(b, 2);
        },
        &begun, 2);
  };
  both();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::uint64_t before = worker.tasks_met_awake();
  both();
  EXPECT_EQ(worker.tasks_met_awake(), before) << "a task 20 ms after the last found the worker spinning";
  for (int k = 0; k < 5; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    both();
  }
  EXPECT_EQ(worker.tasks_met_awake(), before) << "a task 5 ms after the last found the worker spinning";
  EXPECT_EQ(worker.parts_run(), 7u);
}

// The worker, once in a part, is held there until the caller has run every other part: the
// caller takes each part the worker has not begun rather than wait for it (a worker kept off
// its core delays a frame by at most the part it is in). The caller's first part waits until
// the worker has begun one, so that the worker is surely in the game.
TEST(FieldWorker, ThePartsTheWorkerHasNotBegunAreTheCallers) {
  FieldWorker worker;
  constexpr int kParts = 8;
  struct Shared {
    std::thread::id caller = std::this_thread::get_id();
    std::atomic<int> worker_begun{0};
    std::atomic<int> caller_done{0};
    std::atomic<int> runs[kParts] = {};
    std::atomic<bool> timed_out{false};
  } shared;
  worker.run_parts(
      [](void* context, std::size_t part) noexcept {
        Shared& s = *static_cast<Shared*>(context);
        ++s.runs[part];
        if (std::this_thread::get_id() == s.caller) {
          if (s.caller_done.load() == 0 && !wait_for(s.worker_begun, 1)) s.timed_out = true;
          ++s.caller_done;
        } else {
          ++s.worker_begun;
          if (!wait_for(s.caller_done, kParts - 1)) s.timed_out = true;
        }
      },
      &shared, kParts);
  EXPECT_FALSE(shared.timed_out);
  for (int k = 0; k < kParts; ++k) EXPECT_EQ(shared.runs[k].load(), 1) << "part " << k;
  EXPECT_EQ(shared.worker_begun.load(), 1);
  EXPECT_EQ(shared.caller_done.load(), kParts - 1);
  EXPECT_EQ(worker.parts_run(), 1u);
}

// Five forces near a 60,000-point sphere (big enough to be split), global and on an index set.
TEST(FieldWorker, ASplitPassIsBitIdenticalToOneThreadAndItsJournalRestoresEveryByte) {
  const PointModel base = make_sphere(60000);
  std::vector<SourceForce> sources;
  for (int s = 0; s < 5; ++s) sources.push_back({{0.4 * s - 0.8, 0.3, 1.15}, {0.01 * s, -0.02, -0.05}});
  std::vector<std::uint32_t> every_third;
  for (std::uint32_t i = 0; i < base.size(); i += 3) every_third.push_back(i);
  FieldWorker worker;
  // Which thread runs which part is the threads' race: the pass is repeated until the worker
  // has run at least one part of it (every time, the bytes must match).
  for (bool global : {true, false}) {
    for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
      SCOPED_TRACE(std::string(global ? "global " : "index set ") +
                   (precision == Precision::kFloat ? "float" : "double"));
      const std::span<const std::uint32_t> points = global ? std::span<const std::uint32_t>() : every_third;
      PointModel one = base;
      UndoJournal journal_one, journal_two;
      journal_one.reserve(base.size(), true);
      journal_two.reserve(base.size(), true);
      const FieldResult a =
          apply_displacements(one, Kernel{}, sources, points, global, {precision, true}, true, &journal_one);
      EXPECT_FALSE(same_bytes(one, base));  // the pass moved something
      const std::uint64_t before = worker.parts_run();
      for (int attempt = 0; attempt < 50 && worker.parts_run() == before; ++attempt) {
        PointModel two = base;
        const FieldResult b =
            apply_displacements(two, Kernel{}, sources, points, global, {precision, true}, true, &journal_two, &worker);
        EXPECT_TRUE(same_bytes(one, two));
        EXPECT_EQ(a.max_displacement, b.max_displacement);
        EXPECT_EQ(a.min_jacobian, b.min_jacobian);
        EXPECT_EQ(a.finite, b.finite);
        EXPECT_EQ(journal_one.size(), journal_two.size());
        journal_two.restore(two);
        EXPECT_TRUE(same_bytes(two, base));
      }
      EXPECT_GT(worker.parts_run(), before) << "the worker never took a part of the pass";
    }
  }
}

// The parts of a split pass shrink towards its end (so that the two threads finish together):
// whatever the pass's length, they must cover each of its points exactly once. A point left out
// keeps its old position, one in two parts moves twice; either differs from one thread's pass.
// Lengths around the split threshold, off the block size, and with many parts.
TEST(FieldWorker, ThePartsOfASplitPassCoverEveryPointOnce) {
  const PointModel base = make_sphere(140000);
  std::vector<SourceForce> sources;
  for (int s = 0; s < 3; ++s) sources.push_back({{0.5 * s - 0.5, 0.2, 1.2}, {0.01, -0.02, -0.04 * (s + 1)}});
  FieldWorker worker;
  for (const std::uint32_t length : {16384u, 16385u, 33333u, 100003u, 140000u}) {
    SCOPED_TRACE(::testing::Message() << length << " points");
    // Every point of the prefix, in order: the pass's points are an index set of that length.
    std::vector<std::uint32_t> points(length);
    for (std::uint32_t i = 0; i < length; ++i) points[i] = i;
    PointModel one = base, two = base;
    const FieldResult a = apply_displacements(one, Kernel{}, sources, points, false, {Precision::kFloat, true}, true);
    const FieldResult b =
        apply_displacements(two, Kernel{}, sources, points, false, {Precision::kFloat, true}, true, nullptr, &worker);
    EXPECT_TRUE(same_bytes(one, two));
    EXPECT_EQ(a.max_displacement, b.max_displacement);
    EXPECT_EQ(a.min_jacobian, b.min_jacobian);
    // And the points past the prefix stayed where they were (the last part ends at the pass's end).
    for (std::size_t i = length; i < base.size(); i += 997) EXPECT_EQ(two.position(i), base.position(i)) << i;
  }
}

// A stroke of pushes on the 60,000-point sphere, global and in a region, with one thread and
// with two: every frame's output is the next one's input, and the two end byte for byte equal.
TEST(FieldWorker, ADeformerWithTwoThreadsSculptsAStrokeToTheSameBytes) {
  const PointModel base = make_sphere(60000);
  for (bool region : {false, true}) {
    SCOPED_TRACE(region ? "region" : "global");
    PointModel models[2] = {base, base};
    for (int t = 0; t < 2; ++t) {
      DeformSettings s;
      s.contact.bc_radius = 0.02;
      s.contact.min_source_distance = 0.005;
      s.contact.guard_distance = 0.03;
      s.threads = t + 1;
      if (region) {
        s.region.kind = RegionSettings::Kind::kRadius;
        s.region.radius = 1.2;                 // about a third of the sphere: still a split pass
        s.region.global_when_cheaper = false;  // and a region frame, not the cheaper global one
      }
      Deformer d(models[t], s);
      Vec3 previous{0.0, 0.0, 1.05};
      for (int k = 1; k <= 12; ++k) {
        const Vec3 current{0.01 * k, 0.0, 1.0 - 0.004 * k};
        const ProbeMotion m{previous, current, std::nullopt};
        d.deform({&m, 1});
        previous = current;
      }
    }
    EXPECT_FALSE(same_bytes(models[0], base));
    EXPECT_TRUE(same_bytes(models[0], models[1]));
  }
}

TEST(FieldWorker, AThreadCountOtherThanOneOrTwoIsRefused) {
  PointModel m = make_sphere(500);
  DeformSettings s;
  s.threads = 3;
  EXPECT_THROW(Deformer(m, s), std::invalid_argument);
  s.threads = 0;
  EXPECT_THROW(Deformer(m, s), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
