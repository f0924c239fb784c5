// The exact pass works a register of points at a time (16 floats or 8 doubles), with a padded
// copy for a last partial register. Wherever a point falls (first lane, last lane, a partial
// register, a gathered region block), its new position, carried normal and Jacobian must be the
// kernel's own field at that point, computed here one point at a time in double from
// displacement() and displacement_gradient(), and a non-finite result anywhere must be caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/field_worker.hpp"
#include "sculpt/deform/generators.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

struct Expected {
  Vec3 position, normal;
  double det = 0.0;
};

// One point by the kernel's scalar functions: u and grad u summed over the sources, then
// n' = normalize(cof(I + grad u) n) (MATH.md §6) and det(I + grad u).
Expected expected_at(const Kernel& k, const std::vector<SourceForce>& sources, const Vec3& q, const Vec3& n) {
  Vec3 u{};
  double f[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const SourceForce& s : sources) {
    u += displacement(k, s.source, s.force, q);
    const Mat3 g = displacement_gradient(k, s.source, s.force, q);
    for (int l = 0; l < 3; ++l) {
      for (int m = 0; m < 3; ++m) f[l][m] += g(l, m);
    }
  }
  double c[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      c[i][j] = f[i1][j1] * f[i2][j2] - f[i1][j2] * f[i2][j1];
    }
  }
  Expected e;
  e.position = q + u;
  e.det = f[0][0] * c[0][0] + f[0][1] * c[0][1] + f[0][2] * c[0][2];
  const Vec3 m{c[0][0] * n.x + c[0][1] * n.y + c[0][2] * n.z, c[1][0] * n.x + c[1][1] * n.y + c[1][2] * n.z,
               c[2][0] * n.x + c[2][1] * n.y + c[2][2] * n.z};
  e.normal = normalized(m);
  return e;
}

PointModel strip(std::size_t n) {
  PointModel m = make_sphere(std::max<std::size_t>(n, 4));
  PointModel out;
  out.resize(n, true, false);
  for (std::size_t i = 0; i < n; ++i) {
    out.set_position(i, m.position(i));
    out.set_normal(i, m.normal(i));
  }
  return out;
}

const Kernel kKernel{KernelKind::kKelvin, {1.0, 0.4}, 0.0};

std::vector<SourceForce> three_sources() {
  return {{{0.0, 0.0, 1.3}, {0.0, 0.01, -0.04}},
          {{1.2, 0.3, 0.0}, {-0.03, 0.0, 0.01}},
          {{-0.2, -1.25, 0.1}, {0.01, 0.03, 0.0}}};
}

// Every point count up to past two registers, and block edges: each lane position and each
// partial register length is met, contiguous and gathered, in both precisions.
TEST(FieldLanes, EveryPointIsTheKernelsFieldWhereverItFallsInARegister) {
  const std::vector<SourceForce> sources = three_sources();
  std::vector<std::size_t> counts;
  for (std::size_t n = 1; n <= 40; ++n) counts.push_back(n);
  for (std::size_t n : {127u, 128u, 129u, 145u, 300u}) counts.push_back(n);
  for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
    // The model keeps floats: a coordinate near 1 rounds by up to 6e-8 whatever the precision.
    const double tolerance = precision == Precision::kFloat ? 1e-6 : 2e-7;
    for (std::size_t n : counts) {
      for (bool gathered : {false, true}) {
        const PointModel before = strip(n);
        PointModel after = before;
        std::vector<std::uint32_t> indices;
        for (std::size_t i = gathered ? 1 : 0; i < n; i += gathered ? 2 : 1)
          indices.push_back(static_cast<std::uint32_t>(i));
        if (indices.empty()) continue;
        FieldOptions options;
        options.precision = precision;
        const FieldResult r = apply_displacements(after, kKernel, sources, indices, !gathered, options, true);
        SCOPED_TRACE(::testing::Message() << "points " << n << (gathered ? " gathered" : " contiguous")
                                          << (precision == Precision::kFloat ? " float" : " double"));
        ASSERT_TRUE(r.finite);
        double min_det = 1.0;
        std::vector<bool> moved(n, false);
        for (std::uint32_t i : indices) {
          moved[i] = true;
          const Expected e = expected_at(kKernel, sources, before.position(i), before.normal(i));
          min_det = std::min(min_det, e.det);
          EXPECT_LT(norm(after.position(i) - e.position), tolerance) << "point " << i;
          EXPECT_LT(norm(after.normal(i) - e.normal), tolerance) << "point " << i;
        }
        EXPECT_NEAR(r.min_jacobian, min_det, tolerance);
        for (std::size_t i = 0; i < n; ++i) {
          if (moved[i]) continue;
          EXPECT_EQ(after.position(i), before.position(i)) << "point " << i << " was not asked to move";
          EXPECT_EQ(after.normal(i), before.normal(i)) << "point " << i << " was not asked to move";
        }
      }
    }
  }
}

// A point exactly at an unregularised source gets an infinite displacement; wherever it sits
// among the lanes (a full register's first or last, a partial register's last), the pass
// reports it.
TEST(FieldLanes, ANonFiniteResultInAnyLaneIsReported) {
  for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
    for (std::size_t n : {16u, 21u, 40u}) {
      for (std::size_t at : {std::size_t{0}, std::size_t{7}, std::size_t{15}, n - 1}) {
        PointModel m = strip(n);
        const SourceForce on_the_point{m.position(at), {0.0, 0.0, 1.0}};
        FieldOptions options;
        options.precision = precision;
        const FieldResult r = apply_displacements(m, kKernel, {&on_the_point, 1}, {}, true, options, true);
        EXPECT_FALSE(r.finite) << "points " << n << ", at " << at;
      }
    }
  }
}

using test::same_bytes;

// A global pass with a journal as large as the model writes its new values into the journal's
// arrays and trades them for the model's; with a smaller journal, or none, it writes in place.
// All three must leave the same bytes, and the journal must undo its pass exactly, normals
// carried or not, on one thread or two.
TEST(FieldLanes, AGlobalPassWritingBesideTheModelIsThePassInPlaceAndItsJournalUndoesIt) {
  const std::vector<SourceForce> sources = three_sources();
  for (bool carry : {true, false}) {
    for (int threads : {1, 2}) {
      SCOPED_TRACE(::testing::Message() << (carry ? "normals carried" : "positions only") << ", threads " << threads);
      const PointModel before = make_sphere(40000);
      FieldOptions options;
      options.carry_normals = carry;
      FieldWorker worker;
      FieldWorker* split = threads == 2 ? &worker : nullptr;

      PointModel in_place = before;
      apply_displacements(in_place, kKernel, sources, {}, true, options, true, nullptr, split);
      ASSERT_FALSE(same_bytes(in_place, before));

      PointModel small_journal = before;
      UndoJournal partial;
      partial.reserve(before.size() + 1, true);  // not the model's size: records by copying
      apply_displacements(small_journal, kKernel, sources, {}, true, options, true, &partial, split);
      EXPECT_TRUE(same_bytes(small_journal, in_place));

      PointModel aside = before;
      UndoJournal whole;
      whole.reserve(before.size(), true);
      const FieldResult r = apply_displacements(aside, kKernel, sources, {}, true, options, true, &whole, split);
      ASSERT_TRUE(r.finite);
      EXPECT_TRUE(same_bytes(aside, in_place));
      whole.restore(aside);
      EXPECT_TRUE(same_bytes(aside, before));
      partial.restore(small_journal);
      EXPECT_TRUE(same_bytes(small_journal, before));
    }
  }
}

// A gathered pass (a region's) works a block whose points are consecutive in the model in place,
// without gathering it. Whichever way a block goes (consecutive, with a gap, descending, a
// partial last block), each listed point must end at the position the exact global pass gives
// it, to the byte (a point's move depends on its position and the sources alone), with the
// normal that pass carries, or with a bound, its own normal kept (which points keep theirs
// depends on the register they share, so on the lane width and the pass); the others keep
// everything, and the journal undoes the pass exactly.
TEST(FieldLanes, ARegionsConsecutiveBlocksMoveInPlaceByTheSameBytesAsTheGlobalPass) {
  const std::vector<SourceForce> sources = three_sources();
  const PointModel before = make_sphere(2000);
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i < 256; ++i) indices.push_back(i);         // two consecutive blocks
  for (std::uint32_t i = 300; i < 427; ++i) indices.push_back(i);       // 127 consecutive, then
  indices.push_back(500);                                               // a gap in the same block
  for (std::uint32_t i = 0; i < 128; ++i) indices.push_back(1000 - i);  // consecutive but descending
  for (std::uint32_t i = 1100; i < 1300; i += 2) indices.push_back(i);  // scattered
  for (std::uint32_t i = 1500; i < 1700; ++i) indices.push_back(i);     // a run across a block edge
  for (std::uint32_t i = 1901; i < 1950; ++i) indices.push_back(i);     // a consecutive partial last block
  for (bool carry : {true, false}) {
    for (double skip_bound : {0.0, 0.02}) {
      SCOPED_TRACE(::testing::Message() << (carry ? "normals carried" : "positions only") << ", skip bound "
                                        << skip_bound);
      FieldOptions options;
      options.carry_normals = carry;
      PointModel global = before;  // exact
      ASSERT_TRUE(apply_displacements(global, kKernel, sources, {}, true, options, true).finite);
      options.normal_skip_bound = skip_bound;
      PointModel region = before;
      UndoJournal journal;
      journal.reserve(indices.size(), true);
      const FieldResult r = apply_displacements(region, kKernel, sources, indices, false, options, true, &journal);
      ASSERT_TRUE(r.finite);
      if (skip_bound > 0.0) {  // both kinds of point: kept normals, and gradients batched
        EXPECT_GT(r.gradients_skipped, 0u);
        EXPECT_LT(r.gradients_skipped, indices.size());
      }
      std::vector<bool> listed(before.size(), false);
      for (std::uint32_t i : indices) listed[i] = true;
      std::size_t moved = 0, kept = 0;
      for (std::size_t i = 0; i < before.size(); ++i) {
        const PointModel& expected = listed[i] ? global : before;
        ASSERT_EQ(region.position(i), expected.position(i)) << "point " << i << (listed[i] ? " listed" : "");
        const bool kept_own = skip_bound > 0.0 && region.normal(i) == before.normal(i);
        if (!kept_own) {
          ASSERT_EQ(region.normal(i), expected.normal(i)) << "point " << i << (listed[i] ? " listed" : "");
        }
        moved += listed[i] && region.position(i) != before.position(i);
        kept += listed[i] && carry && kept_own;
      }
      EXPECT_GT(moved, indices.size() / 2);
      if (carry && skip_bound > 0.0) {
        EXPECT_GE(kept, r.gradients_skipped);  // more only where a carried normal rounds to the old one
      }
      journal.restore(region);
      EXPECT_TRUE(same_bytes(region, before));
    }
  }
}

}  // namespace
}  // namespace sculpt::deform
