// The bounded normal update (FieldOptions::normal_skip_bound), a named approximation. Checked
// against facts that do not come from the loop:
// - the bound b = sum_s |f_s| ((|alpha| + 5 |gamma|) / r^2 + 3 |beta| / r^4) really bounds
//   ||grad u||_2, the gradient taken by central differences of the kernel's displacement and its
//   norm by an SVD;
// - a pass with the bound moves every point to exactly the bytes of the exact pass, and carries
//   exactly the exact normal wherever b exceeds the setting; where it does not, the normal kept is
//   within asin(b / (1 - b)) of the exact one;
// - the smallest Jacobian it reports is never above the exact one and stays positive, and a frame
//   that folds is seen folding.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/field_worker.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/kernel.hpp"
#include "deform/five_finger_frame.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

// The bound, written from its derivation in the README's physics notes.
double gradient_bound(const KernelCoefficients& k, std::span<const SourceForce> sources, const Vec3& q) {
  double b = 0.0;
  for (const SourceForce& s : sources) {
    const double r2 = squared_norm(q - s.source) + k.eps_squared;
    b += norm(s.force) * ((std::abs(k.alpha) + 5.0 * std::abs(k.gamma)) / r2 + 3.0 * std::abs(k.beta) / (r2 * r2));
  }
  return b;
}

// ||grad u||_2 by central differences of the summed displacement.
double gradient_norm_by_differences(const Kernel& kernel, std::span<const SourceForce> sources, const Vec3& q,
                                    double h) {
  Eigen::Matrix3d g;
  for (int m = 0; m < 3; ++m) {
    Vec3 step{};
    (m == 0 ? step.x : m == 1 ? step.y : step.z) = h;
    Vec3 plus{}, minus{};
    for (const SourceForce& s : sources) {
      plus = plus + displacement(kernel, s.source, s.force, q + step);
      minus = minus + displacement(kernel, s.source, s.force, q - step);
    }
    const Vec3 d = (plus - minus) * (1.0 / (2.0 * h));
    g(0, m) = d.x;
    g(1, m) = d.y;
    g(2, m) = d.z;
  }
  return Eigen::JacobiSVD<Eigen::Matrix3d>(g).singularValues()(0);
}

Kernel regularized(double eps, double nu) {
  Kernel k;
  k.kind = KernelKind::kRegularized;
  k.regularization = eps;
  k.material.poisson_ratio = nu;
  return k;
}

TEST(BoundedNormals, TheBoundIsAboveTheGradientsNormEverywhere) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Kernel& kernel : {Kernel{}, regularized(0.05, 0.3), regularized(0.2, 0.499), regularized(0.01, -0.9)}) {
    const KernelCoefficients k = coefficients(kernel);
    for (int trial = 0; trial < 400; ++trial) {
      std::vector<SourceForce> sources;
      for (int s = 0; s < 1 + trial % 5; ++s) {
        sources.push_back({{u(rng), u(rng), u(rng)}, {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)}});
      }
      const Vec3 q{u(rng), u(rng), u(rng)};
      double nearest = 1e9;
      for (const SourceForce& s : sources) nearest = std::min(nearest, norm(q - s.source));
      if (kernel.kind == KernelKind::kKelvin && nearest < 0.05) continue;  // singular there
      const double exact = gradient_norm_by_differences(kernel, sources, q, 1e-5 * std::max(nearest, 1e-2));
      const double bound = gradient_bound(k, sources, q);
      ASSERT_LE(exact, bound * (1.0 + 1e-6)) << "trial " << trial;
      // Not a bound so loose that it never lets a point be skipped: for one source (several
      // may cancel) within a factor of 20.
      if (sources.size() == 1) {
        EXPECT_GT(exact, bound / 20.0) << "trial " << trial;
      }
    }
  }
}

using frames::five_fingers;
using frames::Frame;
using test::same_bytes;

double angle(double ax, double ay, double az, double bx, double by, double bz) {
  const double c =
      (ax * bx + ay * by + az * bz) / std::sqrt((ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz));
  return std::acos(std::clamp(c, -1.0, 1.0));
}

TEST(BoundedNormals, PositionsAreExactAndEachNormalIsExactOrWithinItsBound) {
  const Frame f = five_fingers();
  const Kernel kernel{};
  const KernelCoefficients k = coefficients(kernel);
  for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
    for (double tolerance : {2e-3, 1e-2, 5e-2}) {
      SCOPED_TRACE(testing::Message() << (precision == Precision::kFloat ? "float" : "double") << " bound "
                                      << tolerance);
      PointModel exact = f.base, bounded = f.base;
      const FieldResult e = apply_displacements(exact, kernel, f.sources, {}, true, {precision, true, 0.0}, true);
      const FieldResult b =
          apply_displacements(bounded, kernel, f.sources, {}, true, {precision, true, tolerance}, true);
      EXPECT_TRUE(same_bytes(exact.x, bounded.x) && same_bytes(exact.y, bounded.y) && same_bytes(exact.z, bounded.z));
      EXPECT_EQ(e.max_displacement, b.max_displacement);
      EXPECT_EQ(e.gradients_skipped, 0u);
      std::size_t computed = 0, skippable = 0, edge = 0, kept = 0;
      double worst_kept = 0.0;
      for (std::size_t i = 0; i < f.base.size(); ++i) {
        const Vec3 q{f.base.x[i], f.base.y[i], f.base.z[i]};
        const double bound = gradient_bound(k, f.sources, q);
        // The loop's bound is summed in its own precision: leave out the points at the edge.
        if (std::abs(bound - tolerance) < 1e-3 * tolerance) {
          ++edge;
          continue;
        }
        if (bound > tolerance) {
          ++computed;
          ASSERT_TRUE(exact.nx[i] == bounded.nx[i] && exact.ny[i] == bounded.ny[i] && exact.nz[i] == bounded.nz[i])
              << "point " << i;
        } else {
          // Kept, or carried exactly (a block where most points need their gradient is computed
          // whole).
          ++skippable;
          const bool old =
              f.base.nx[i] == bounded.nx[i] && f.base.ny[i] == bounded.ny[i] && f.base.nz[i] == bounded.nz[i];
          const bool carried =
              exact.nx[i] == bounded.nx[i] && exact.ny[i] == bounded.ny[i] && exact.nz[i] == bounded.nz[i];
          ASSERT_TRUE(old || carried) << "point " << i;
          if (old && !carried) {
            ++kept;
            worst_kept = std::max(worst_kept, bound);
          }
          const double off = angle(exact.nx[i], exact.ny[i], exact.nz[i], bounded.nx[i], bounded.ny[i], bounded.nz[i]);
          // The exact normal is itself rounded to float: 1e-6 rad of slack.
          ASSERT_LE(off, std::asin(bound / (1.0 - bound)) + 1e-6) << "point " << i;
        }
      }
      EXPECT_GT(computed, 0u);
      EXPECT_GT(kept, skippable / 2);  // the setting acted, on most of the points it may act on
      // It counts every point it left, and no more than could be left.
      EXPECT_GE(b.gradients_skipped, kept);
      EXPECT_LE(b.gradients_skipped, skippable + edge);
      EXPECT_LE(b.max_skipped_bound, tolerance);
      // The largest bound it reports holds for every point it left (a block's bound holds for
      // each of its points).
      EXPECT_GE(b.max_skipped_bound, worst_kept * (1.0 - 1e-5));
      // The Jacobian it reports is a floor: never above the exact minimum, and positive.
      EXPECT_LE(b.min_jacobian, e.min_jacobian);
      EXPECT_GT(b.min_jacobian, 0.0);
    }
  }
}

// The bounded pass's batch works by point index in a global pass (into the journal's arrays
// when it writes aside) and within each gathered block in a region pass. The same frame run in
// place, aside, on two threads and as a region listing every point must leave the same bytes,
// and the journal written aside must undo it.
TEST(BoundedNormals, InPlaceAsideOnTwoThreadsAndGatheredTheBytesAreTheSame) {
  const Frame f = five_fingers();
  std::vector<std::uint32_t> every_point(f.base.size());
  for (std::size_t i = 0; i < every_point.size(); ++i) every_point[i] = static_cast<std::uint32_t>(i);
  for (Precision precision : {Precision::kFloat, Precision::kDouble}) {
    SCOPED_TRACE(precision == Precision::kFloat ? "float" : "double");
    const FieldOptions options{precision, true, 1e-2};
    PointModel in_place = f.base;
    const FieldResult r = apply_displacements(in_place, Kernel{}, f.sources, {}, true, options, true);
    ASSERT_GT(r.gradients_skipped, 0u);
    ASSERT_LT(r.gradients_skipped, f.base.size());

    PointModel aside = f.base;
    UndoJournal journal;
    journal.reserve(f.base.size(), true);
    FieldWorker worker;
    const FieldResult a = apply_displacements(aside, Kernel{}, f.sources, {}, true, options, true, &journal, &worker);
    EXPECT_TRUE(same_bytes(aside.x, in_place.x) && same_bytes(aside.y, in_place.y) && same_bytes(aside.z, in_place.z));
    EXPECT_TRUE(same_bytes(aside.nx, in_place.nx) && same_bytes(aside.ny, in_place.ny) &&
                same_bytes(aside.nz, in_place.nz));
    EXPECT_EQ(a.gradients_skipped, r.gradients_skipped);
    journal.restore(aside);
    EXPECT_TRUE(same_bytes(aside.x, f.base.x) && same_bytes(aside.nx, f.base.nx) && same_bytes(aside.nz, f.base.nz));

    PointModel gathered = f.base;
    const FieldResult g = apply_displacements(gathered, Kernel{}, f.sources, every_point, false, options, true);
    EXPECT_TRUE(same_bytes(gathered.x, in_place.x) && same_bytes(gathered.y, in_place.y) &&
                same_bytes(gathered.z, in_place.z));
    EXPECT_TRUE(same_bytes(gathered.nx, in_place.nx) && same_bytes(gathered.ny, in_place.ny) &&
                same_bytes(gathered.nz, in_place.nz));
    EXPECT_EQ(g.gradients_skipped, r.gradients_skipped);
    EXPECT_EQ(g.min_jacobian, r.min_jacobian);
  }
}

TEST(BoundedNormals, AFrameThatFoldsIsSeenFolding) {
  Frame f = five_fingers();
  for (SourceForce& s : f.sources) s.force = s.force * 40.0;  // far past the fold
  PointModel exact = f.base, bounded = f.base;
  const FieldResult e = apply_displacements(exact, Kernel{}, f.sources, {}, true, {Precision::kFloat, true, 0.0}, true);
  const FieldResult b =
      apply_displacements(bounded, Kernel{}, f.sources, {}, true, {Precision::kFloat, true, 0.1}, true);
  ASSERT_LE(e.min_jacobian, 0.0);
  EXPECT_EQ(b.min_jacobian, e.min_jacobian);  // the fold is where the gradient is computed
  EXPECT_GT(b.gradients_skipped, 0u);
}

// Half the model, as an index set (a pass over it gathers and scatters its blocks).
std::vector<std::uint32_t> every_other_point(const PointModel& m) {
  std::vector<std::uint32_t> points;
  for (std::uint32_t i = 0; i < m.size(); i += 2) points.push_back(i);
  return points;
}

TEST(BoundedNormals, AnIndexSetAndTheSecondCoreGiveTheSameBytes) {
  const Frame f = five_fingers();
  const std::vector<std::uint32_t> every_other = every_other_point(f.base);
  FieldWorker worker;
  for (bool global : {true, false}) {
    SCOPED_TRACE(global ? "global" : "index set");
    const std::span<const std::uint32_t> points = global ? std::span<const std::uint32_t>() : every_other;
    PointModel one = f.base, two = f.base;
    UndoJournal journal;
    journal.reserve(f.base.size(), true);
    const FieldOptions options{Precision::kFloat, true, 1e-2};
    const FieldResult a = apply_displacements(one, Kernel{}, f.sources, points, global, options, true);
    const FieldResult b =
        apply_displacements(two, Kernel{}, f.sources, points, global, options, true, &journal, &worker);
    EXPECT_TRUE(same_bytes(one.x, two.x) && same_bytes(one.nx, two.nx) && same_bytes(one.ny, two.ny) &&
                same_bytes(one.nz, two.nz));
    EXPECT_EQ(a.gradients_skipped, b.gradients_skipped);
    EXPECT_EQ(a.max_skipped_bound, b.max_skipped_bound);
    EXPECT_EQ(a.min_jacobian, b.min_jacobian);
    EXPECT_GT(a.gradients_skipped, 0u);
    // The journal undoes the bounded pass to the last byte, normals included.
    journal.restore(two);
    EXPECT_TRUE(same_bytes(two.x, f.base.x) && same_bytes(two.nx, f.base.nx) && same_bytes(two.nz, f.base.nz));
  }
}

// A bounded pass leaves the normals of the blocks it skips untouched and does not journal them.
// The journal still holds an earlier pass's normals there: undoing the bounded pass must not
// write those back. An exact pass first (it moves every normal), then a bounded one on the same
// journal, then the undo: the model must be the exact pass's, to the byte.
TEST(BoundedNormals, UndoingABoundedPassLeavesTheNormalsItSkippedAsTheyWere) {
  const Frame f = five_fingers();
  const std::vector<std::uint32_t> every_other = every_other_point(f.base);
  FieldWorker worker;
  for (bool global : {true, false}) {
    for (FieldWorker* second : {static_cast<FieldWorker*>(nullptr), &worker}) {
      SCOPED_TRACE(std::string(global ? "global" : "index set") + (second ? ", two cores" : ", one core"));
      const std::span<const std::uint32_t> points = global ? std::span<const std::uint32_t>() : every_other;
      PointModel model = f.base;
      UndoJournal journal;
      journal.reserve(f.base.size(), true);
      const FieldOptions exact{Precision::kFloat, true, 0.0};
      ASSERT_TRUE(
          apply_displacements(model, Kernel{}, f.sources, points, global, exact, true, &journal, second).finite);
      const PointModel after_exact = model;
      ASSERT_FALSE(same_bytes(after_exact.nx, f.base.nx));
      const FieldOptions bounded{Precision::kFloat, true, 1e-2};
      const FieldResult r =
          apply_displacements(model, Kernel{}, f.sources, points, global, bounded, true, &journal, second);
      ASSERT_TRUE(r.finite);
      EXPECT_GT(r.gradients_skipped, 0u);
      journal.restore(model);
      EXPECT_TRUE(same_bytes(model.x, after_exact.x) && same_bytes(model.y, after_exact.y) &&
                  same_bytes(model.z, after_exact.z));
      EXPECT_TRUE(same_bytes(model.nx, after_exact.nx) && same_bytes(model.ny, after_exact.ny) &&
                  same_bytes(model.nz, after_exact.nz));
    }
  }
}

}  // namespace
}  // namespace sculpt::deform
