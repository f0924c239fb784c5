// The second core: a persistent worker takes half of a large displacement pass. The result must
// be bit for bit what one thread makes (every per-point value is computed by the same code from
// the same inputs, and the extremes reduce exactly), the worker must really run on another
// thread, the undo journal of a split pass must restore every byte, and a deformer with two
// threads must sculpt a stroke to exactly the bytes one thread makes.

#include "sculpt/deform/field_worker.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/generators.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

using test::same_bytes;

TEST(FieldWorker, RunsTheSecondPartOnAnotherThreadAndWaitsForIt) {
  FieldWorker worker;
  struct Seen {
    std::thread::id id[2];
    int calls[2] = {0, 0};
  } seen;
  for (int round = 0; round < 1000; ++round) {
    worker.run_both(
        [](void* context, int part) noexcept {
          Seen& s = *static_cast<Seen*>(context);
          s.id[part] = std::this_thread::get_id();
          ++s.calls[part];
        },
        &seen);
    // Returned only once both parts ran: the counts never lag.
    ASSERT_EQ(seen.calls[0], round + 1);
    ASSERT_EQ(seen.calls[1], round + 1);
  }
  EXPECT_EQ(seen.id[0], std::this_thread::get_id());
  EXPECT_NE(seen.id[1], std::this_thread::get_id());
  EXPECT_EQ(worker.tasks_run(), 1000u);
}

// Five forces near a 60,000-point sphere (big enough to be split), global and on an index set.
TEST(FieldWorker, ASplitPassIsBitIdenticalToOneThreadAndItsJournalRestoresEveryByte) {
  const PointModel base = make_sphere(60000);
  std::vector<SourceForce> sources;
  for (int s = 0; s < 5; ++s) sources.push_back({{0.4 * s - 0.8, 0.3, 1.15}, {0.01 * s, -0.02, -0.05}});
  std::vector<std::uint32_t> every_third;
  for (std::uint32_t i = 0; i < base.size(); i += 3) every_third.push_back(i);
  FieldWorker worker;
  for (bool global : {true, false}) {
    for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
      SCOPED_TRACE(std::string(global ? "global " : "index set ") +
                   (precision == Precision::kFloat ? "float" : "double"));
      const std::span<const std::uint32_t> points = global ? std::span<const std::uint32_t>() : every_third;
      PointModel one = base, two = base;
      UndoJournal journal_one, journal_two;
      journal_one.reserve(base.size(), true);
      journal_two.reserve(base.size(), true);
      const FieldResult a =
          apply_displacements(one, Kernel{}, sources, points, global, {precision, true}, true, &journal_one);
      const FieldResult b =
          apply_displacements(two, Kernel{}, sources, points, global, {precision, true}, true, &journal_two, &worker);
      EXPECT_FALSE(same_bytes(one, base));  // the pass moved something
      EXPECT_TRUE(same_bytes(one, two));
      EXPECT_EQ(a.max_displacement, b.max_displacement);
      EXPECT_EQ(a.min_jacobian, b.min_jacobian);
      EXPECT_EQ(a.finite, b.finite);
      EXPECT_EQ(journal_one.size(), journal_two.size());
      journal_two.restore(two);
      EXPECT_TRUE(same_bytes(two, base));
    }
  }
  EXPECT_EQ(worker.tasks_run(), 4u);
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
        s.region.radius = 1.2;  // about a third of the sphere: still a split pass
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
