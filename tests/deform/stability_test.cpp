// Strokes, not presses: sequences of frames, each deforming the last one's output, and the
// hostile single frames that broke them (issue 7's findings). Every expectation comes from
// geometry or a formula, never from the code's own output captured once.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/weight_solver.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

DeformSettings settings_for(double spacing) {
  DeformSettings s;
  s.kernel = {KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  s.contact.bc_radius = spacing;
  s.contact.min_source_distance = 0.25 * spacing;
  s.contact.guard_distance = 1.5 * spacing;
  return s;
}

constexpr double kSphereSpacing = 0.063;  // the 3,203-point unit sphere's lattice pitch

bool all_finite(const PointModel& m) {
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!is_finite(m.position(i))) return false;
    if (m.has_normals() && !is_finite(m.normal(i))) return false;
  }
  return true;
}

using test::same_bytes;

double min_distance_to_points(const PointModel& m, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i) best = std::min(best, norm(m.position(i) - q));
  return best;
}

double largest_step(const PointModel& before, const PointModel& after) {
  double worst = 0.0;
  for (std::size_t i = 0; i < before.size(); ++i) worst = std::max(worst, norm(after.position(i) - before.position(i)));
  return worst;
}

// Depth of q below a surface that faces +axis locally: the highest model point within `radius`
// of the axis line through q, minus q's height. Independent of the carried normals.
double depth_below_top(const PointModel& m, const Vec3& q, double radius) {
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 p = m.position(i);
    if (std::hypot(p.x - q.x, p.y - q.y) <= radius) top = std::max(top, p.z);
  }
  return top - q.z;
}

// One finger walking a path: each frame's previous position is where the last frame left the
// finger (pushed out or not), as the station's dead band does.
struct Finger {
  Vec3 at;
  std::optional<Vec3> before;
  const FrameReport& move(Deformer& d, const Vec3& next) {
    const ProbeMotion m{at, next, before};
    const FrameReport& r = d.deform({&m, 1});
    before = at;
    at = r.contacts[0].probe_after;
    return r;
  }
};

// Finding 1: a slide puts the new source (the previous probe position) on the point the last
// press moved onto the probe. Every source must keep Δd from every model point, and nothing
// may go NaN or fly off.
TEST(Stability, SlidingStrokeOnASheetKeepsEverySourceClearAndTheSheetFinite) {
  const double pitch = 0.01;
  PointModel sheet = make_plane_patch(61, pitch);
  Deformer d(sheet, settings_for(pitch));
  Finger f{{0.0, 0.0, 0.01}, std::nullopt};
  f.move(d, {0.0, 0.0, -0.01});
  for (int k = 1; k <= 60; ++k) {
    const PointModel before = sheet;
    const Vec3 next{0.004 * k, 0.0, -0.01};
    const FrameReport& r = f.move(d, next);
    ASSERT_TRUE(all_finite(sheet)) << "frame " << k;
    for (const FrameReport& applied : d.frames()) {
      ASSERT_GT(applied.min_jacobian, d.settings().guards.min_jacobian) << "frame " << k;
    }
    if (r.collisions == 0) continue;
    const ContactReport& c = r.contacts[0];
    // The clearance is checked against the model the frame started from.
    if (d.frames().size() == 1) {
      EXPECT_GE(min_distance_to_points(before, c.source), 0.999999 * d.settings().contact.min_source_distance)
          << "frame " << k;
    }
    // A frame moves points at most a few times the depth it imposes (was 4.8e5 units).
    EXPECT_LT(largest_step(before, sheet), 3.0 * norm(c.force) + 1e-9) << "frame " << k;
  }
}

TEST(Stability, SourceAMicronAboveAPointIsMovedClear) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer d(sphere, settings_for(kSphereSpacing));
  const Vec3 a = sphere.position(0);  // the lattice's first point, near the north pole
  const Vec3 n = sphere.normal(0);
  const ProbeMotion m{a + n * 1e-6, a - n * 0.02, std::nullopt};
  const FrameReport& r = d.deform({&m, 1});
  ASSERT_EQ(r.collisions, 1u);
  EXPECT_EQ(r.contacts[0].source_rule, SourceRule::kCleared);
  EXPECT_GE(r.guards.source_moved, 1u);
  EXPECT_GE(min_distance_to_points(before, r.contacts[0].source), 0.999999 * 2.0 * norm(r.contacts[0].force));
  EXPECT_TRUE(all_finite(sphere));
  EXPECT_LT(largest_step(before, sphere), 3.0 * norm(r.contacts[0].force));  // was 917 units
}

// A carried normal tilted nearly into the surface leaves the source no clear place: -F is not
// on the allowed side, and along A's normal every place tried has a model point closer than
// half its distance to A. The source must then stand where it is most alone, never on the last
// place tried whatever is there (here a stray point sits on it: a source on a model point
// moves that point without bound).
TEST(Stability, WhenNoPlaceTriedIsClearTheSourceStandsWhereItIsMostAlone) {
  const double pitch = 0.05;
  PointModel sheet = make_plane_patch(41, pitch);
  const std::size_t a = sheet.size() / 2;  // the centre, at the origin
  ASSERT_LT(norm(sheet.position(a)), 1e-12);
  const double tilt = 80.0 * M_PI / 180.0;
  const Vec3 tilted{std::sin(tilt), 0.0, std::cos(tilt)};
  sheet.set_normal(a, tilted);
  const DeformSettings settings = settings_for(pitch);
  // The places the deformer tries along A's normal: the clearance (eps here) doubled 3 times.
  const double clearance = settings.contact.bc_radius;
  const Vec3 last_tried = tilted * (8.0 * clearance);
  sheet.push_back(last_tried);
  sheet.set_normal(sheet.size() - 1, {0.0, 0.0, 1.0});
  const PointModel before = sheet;
  Deformer d(sheet, settings);
  const ProbeMotion m{{0.0, 0.0, 0.3 * clearance}, {0.0, 0.0, -0.2 * clearance}, std::nullopt};
  const FrameReport& r = d.deform({&m, 1});
  ASSERT_FALSE(d.frames().empty());
  const ContactReport& c = d.frames().front().contacts[0];  // substeps hold its source
  ASSERT_EQ(c.state, ProbeState::kCollided);
  EXPECT_EQ(c.source_rule, SourceRule::kCleared);
  // How alone each candidate stands: nearest point's distance over what it must keep.
  auto alone = [&](const Vec3& p) {
    return min_distance_to_points(before, p) / std::max(clearance, 0.5 * norm(p - before.position(a)));
  };
  double best = alone(m.previous);
  for (double k : {1.0, 2.0, 4.0, 8.0}) best = std::max(best, alone(tilted * (k * clearance)));
  ASSERT_LT(best, 1.0);  // no place was clear: the fallback is what is tested
  EXPECT_NEAR(alone(c.source), best, 1e-6);
  EXPECT_GT(norm(c.source - last_tried), clearance);
  EXPECT_EQ(r.guards.non_finite, 0u);
  EXPECT_TRUE(all_finite(sheet));
}

// Finding 2: a non-finite result is caught, not hidden by a NaN-blind maximum, and undone bit
// for bit through the journal.
TEST(Stability, NonFiniteDisplacementIsReportedAndTheJournalRestoresTheBytes) {
  PointModel m = make_sphere(200);
  const PointModel before = m;
  const SourceForce on_a_point{m.position(7), {0.0, 0.0, 1.0}};  // R = 0 at point 7: 1/R
  UndoJournal journal;
  journal.reserve(m.size(), m.has_normals());
  const FieldResult r = apply_displacements(m, Kernel{}, {&on_a_point, 1}, {}, true, {}, true, &journal);
  EXPECT_FALSE(r.finite);
  journal.restore(m);
  EXPECT_TRUE(same_bytes(m, before));
}

// A pass that does not carry normals leaves them alone, so its undo must too: after a pass
// that carried normals (the journal then held them), a pass without them is undone to exactly
// the model before it, not to the first pass's normals.
TEST(Stability, UndoingAPassThatCarriedNoNormalsLeavesTheNormalsAsTheyAre) {
  PointModel m = make_sphere(200);
  UndoJournal journal;
  journal.reserve(m.size(), m.has_normals());
  const SourceForce push{{0.0, 0.0, 1.5}, {0.0, 0.0, -0.05}};
  apply_displacements(m, Kernel{}, {&push, 1}, {}, true, {}, true, &journal);
  const PointModel after_first = m;
  FieldOptions positions_only;
  positions_only.carry_normals = false;
  apply_displacements(m, Kernel{}, {&push, 1}, {}, true, positions_only, true, &journal);
  journal.restore(m);
  EXPECT_TRUE(same_bytes(m, after_first));
}

// Finding 3: on the force axis det(I + grad u) = (1 - U/h)(1 + U/(4(1 - nu)h))^2 (MATH.md §6);
// the frame's reported minimum can be no larger than that at A.
TEST(Stability, JacobianOnTheForceAxisMatchesTheClosedForm) {
  for (double nu : {0.0, 0.3, 0.45}) {
    const double h = 0.3, f = 1e-3;
    const Kernel k{KernelKind::kKelvin, {1.0, nu}, 0.0};
    PointModel m;
    m.push_back({0.0, 0.0, 0.0});
    const SourceForce s{{0.0, 0.0, h}, {0.0, 0.0, -f}};  // pushes the point away, along -z
    const double u = norm(displacement(k, s.source, s.force, {0.0, 0.0, 0.0}));
    const FieldResult r = apply_displacements(m, k, {&s, 1}, {}, true, {Precision::kDouble, false}, true);
    const double expected = (1.0 - u / h) * std::pow(1.0 + u / (4.0 * (1.0 - nu) * h), 2.0);
    EXPECT_NEAR(r.min_jacobian, expected, 1e-9) << "nu " << nu;
  }
}

// Finding 3: a push deeper than the source's distance folds; the frame is split into substeps
// that each keep det > the guard and the normals outward, and the finger never passes through.
TEST(Stability, DeepPressFromACloseSourceIsSplitIntoSubstepsThatDoNotFold) {
  PointModel sphere = make_sphere();
  DeformSettings s = settings_for(kSphereSpacing);
  s.guards.clearance_ratio = 0.0;  // only Δd: the thesis's rule, which lets the frame fold
  Deformer d(sphere, s);
  const Vec3 n = sphere.normal(0), a = sphere.position(0);
  const ProbeMotion m{a + n * 0.02, a - n * 0.2, std::nullopt};
  const FrameReport& r = d.deform({&m, 1});
  EXPECT_GE(r.guards.fold_splits, 1u);
  ASSERT_GT(d.frames().size(), 1u);
  EXPECT_GT(r.min_jacobian, s.guards.min_jacobian);
  // The substeps carry the surface to the probe: the step as a whole presses 0.2.
  EXPECT_NEAR(dot(sphere.position(0) - a, -n), 0.2, 0.05);
  // Normals at the contact still face out (the old F^-T normal flipped inward here).
  EXPECT_GT(dot(sphere.normal(0), n), 0.0);
  EXPECT_TRUE(all_finite(sphere));
}

// Finding 3, as a stroke: 50 pushes of 0.02 straight into the sphere, 1.0 deep. Every frame
// presses (none is `free` while the finger is inside) and the finger never ends inside.
TEST(Stability, StraightPushOneDeepNeverPassesThrough) {
  PointModel sphere = make_sphere();
  Deformer d(sphere, settings_for(kSphereSpacing));
  const double dd = d.settings().contact.min_source_distance;
  Finger f{{0.0, 0.0, 1.05}, std::nullopt};
  int pressed = 0;
  for (int k = 1; k <= 52; ++k) {
    const FrameReport& r = f.move(d, {0.0, 0.0, 1.04 - 0.02 * k});
    const ContactReport& c = r.contacts[0];
    if (k > 3) {
      EXPECT_EQ(c.state, ProbeState::kCollided) << "frame " << k;
    }
    if (c.state == ProbeState::kCollided) ++pressed;
    EXPECT_LE(depth_below_top(sphere, f.at, 0.5 * kSphereSpacing), dd + 1e-6) << "frame " << k;
    ASSERT_TRUE(all_finite(sphere));
  }
  EXPECT_GE(pressed, 48);
}

// Finding 4: two fingers at one contact; the deeper one may not be left inside, or it would be
// `started_inside` for good.
TEST(Stability, TwoFingersAtOneContactBothEndOutsideAndKeepPressing) {
  PointModel sphere = make_sphere();
  Deformer d(sphere, settings_for(kSphereSpacing));
  const double dd = d.settings().contact.min_source_distance;
  const Vec3 a = sphere.position(0), n = sphere.normal(0);
  const Vec3 t = normalized(cross(n, {1.0, 0.0, 0.0}));
  ProbeMotion both[2] = {{a + n * 0.05, a - n * 0.02, std::nullopt},
                         {a + t * 0.01 + n * 0.05, a + t * 0.01 - n * 0.07, std::nullopt}};
  for (int frame = 0; frame < 3; ++frame) {
    const FrameReport& r = d.deform(both);
    for (int p = 0; p < 2; ++p) {
      const ContactReport& c = r.contacts[p];
      EXPECT_NE(c.state, ProbeState::kStartedInside) << "frame " << frame << " finger " << p;
      EXPECT_LE(-c.side_after, dd + 1e-9) << "frame " << frame << " finger " << p;
      both[p].previous = c.probe_after;
      both[p].current = c.probe_after - n * 0.01;
    }
  }
  EXPECT_TRUE(all_finite(sphere));
}

// Finding 5: the damped solve is reachable. Two sources 1e-9 apart are all but the same
// column pair: condition ~1e9, above max_condition 1e8 and below the truncation at 1e13.
TEST(Stability, NearlyCoincidentSourcesFallBackToTheDampedSolve) {
  const Kernel k{KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  const SourceSetup sources[2] = {{{0.0, 0.0, 0.1}, {0.0, 0.0, -0.01}}, {{1e-9, 0.0, 0.1}, {0.0, 0.0, -0.01}}};
  std::vector<DisplacementCondition> conditions;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j) conditions.push_back({{0.02 * i, 0.02 * j, 0.0}, {0.0, 0.0, -0.01}, 1.0});
  Vec3 w[2], f[2];
  const SolveReport r = WeightSolver({WeightForm::kForce}).solve(k, sources, conditions, {}, w, f);
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(r.damped);
  EXPECT_GT(r.condition, 1e8);
  // Damping keeps the pair from cancelling with huge opposite forces.
  EXPECT_LT(norm(f[0]), 1e3 * norm(f[0] + f[1]));
  SolverOptions never;
  never.rank_tolerance = 1e-10;
  never.max_condition = 1e10;
  EXPECT_THROW(never.validate(), std::invalid_argument);
}

// Finding 6: the default form is continuous (float noise in F changes nothing visible) and
// turns with the model; the scale form no longer jumps on noise either.
TEST(Stability, EffectiveForcesAreContinuousAndTurnWithTheModel) {
  for (const WeightForm form : {WeightForm::kForce, WeightForm::kScale}) {
    const Kernel k{KernelKind::kKelvin, {3e7, 0.45}, 0.0};
    auto solve = [&](double fx, const Mat3& rot) {
      auto turn = [&](const Vec3& v) {
        return Vec3{rot(0, 0) * v.x + rot(0, 1) * v.y + rot(0, 2) * v.z,
                    rot(1, 0) * v.x + rot(1, 1) * v.y + rot(1, 2) * v.z,
                    rot(2, 0) * v.x + rot(2, 1) * v.y + rot(2, 2) * v.z};
      };
      const SourceSetup s[2] = {{turn({-0.2, 0.0, 0.1}), turn({fx, 0.0, -0.01})},
                                {turn({0.2, 0.0, 0.1}), turn({0.0, 0.0, -0.01})}};
      std::vector<DisplacementCondition> c;
      for (double x : {-0.2, 0.2})
        for (int i = -2; i <= 2; ++i)
          for (int j = -2; j <= 2; ++j)
            c.push_back({turn({x + 0.02 * i, 0.02 * j, 0.0}), turn({0.0, 0.0, -0.01}), 1.0});
      Vec3 w[2], f[2];
      (void)WeightSolver({form}).solve(k, s, c, {}, w, f);
      return std::array<Vec3, 2>{f[0], f[1]};
    };
    Mat3 identity;
    identity(0, 0) = identity(1, 1) = identity(2, 2) = 1.0;
    const auto exact = solve(0.0, identity);
    const auto noisy = solve(-1.2e-8, identity);
    for (int i = 0; i < 2; ++i) EXPECT_LT(norm(exact[i] - noisy[i]), 1e-4 * norm(exact[i]));
    if (form != WeightForm::kForce) continue;
    // A rotation about a non-axis direction; the effective forces must rotate with it.
    const double c = std::cos(0.7), sn = std::sin(0.7);
    Mat3 rot;  // about (1, 1, 1)/sqrt(3), Rodrigues
    const double ax[3] = {1 / std::sqrt(3.0), 1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) {
        const double cross_term = (r == q) ? 0.0 : (((q - r + 3) % 3 == 1) ? -ax[3 - r - q] : ax[3 - r - q]);
        rot(r, q) = (r == q ? c : 0.0) + (1 - c) * ax[r] * ax[q] + sn * cross_term;
      }
    const auto turned = solve(0.0, rot);
    for (int i = 0; i < 2; ++i) {
      const Vec3 e = exact[i];
      const Vec3 expected{rot(0, 0) * e.x + rot(0, 1) * e.y + rot(0, 2) * e.z,
                          rot(1, 0) * e.x + rot(1, 1) * e.y + rot(1, 2) * e.z,
                          rot(2, 0) * e.x + rot(2, 1) * e.y + rot(2, 2) * e.z};
      EXPECT_LT(norm(turned[i] - expected), 1e-6 * norm(e));
    }
  }
}

// Finding 7: 200 pushes of 0.005 must carry a patch the finger's size, not drag one point.
TEST(Stability, LongPushCarriesAPatchNotANeedle) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer d(sphere, settings_for(kSphereSpacing));
  Finger f{{0.0, 0.0, 1.01}, std::nullopt};
  for (int k = 1; k <= 200; ++k) f.move(d, {0.0, 0.0, 1.0 - 0.005 * k});
  ASSERT_TRUE(all_finite(sphere));
  std::size_t far = 0;
  double deepest = 0.0;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    const double moved = norm(sphere.position(i) - before.position(i));
    deepest = std::max(deepest, moved);
    if (moved > 0.1) ++far;
  }
  EXPECT_GT(deepest, 0.5);  // the finger went about 1.0 in
  EXPECT_GE(far, 5u);       // the eps-ball of the lattice holds about 3; the patch follows it
}

// Finding 8: without normals the side is a length: the same press collides the same way
// whether the reference point stands at z = 2 or z = 10.
TEST(Stability, ReferencePointSideDoesNotDependOnTheReferenceDistance) {
  for (double zr : {2.0, 10.0}) {
    PointModel sphere = make_sphere();
    sphere.clear_normals();
    DeformSettings s = settings_for(kSphereSpacing);
    s.contact.reference = Vec3{0.0, 0.0, zr};
    Deformer d(sphere, s);
    const Vec3 a = sphere.position(0);
    const ProbeMotion first{a * 1.05, a * 0.99, std::nullopt};
    const FrameReport& r = d.deform({&first, 1});
    EXPECT_EQ(r.contacts[0].state, ProbeState::kCollided) << "reference z " << zr;
    const ProbeMotion second{r.contacts[0].probe_after, a * 0.98, first.previous};
    EXPECT_EQ(d.deform({&second, 1}).contacts[0].state, ProbeState::kCollided) << "reference z " << zr;
  }
}

// Finding 10: a fingertip at 1e30 (valid CRC, absurd value) or NaN is dropped and counted; the
// model stays bit for bit as it was.
TEST(Stability, OutOfRangeOrNonFiniteProbesAreDroppedAndCounted) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer d(sphere, settings_for(kSphereSpacing));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ProbeMotion bad[3] = {{{0.0, 0.0, 1.1}, {0.0, 0.0, 1e30}, std::nullopt},
                              {{0.0, 0.0, 1e20}, {0.0, 0.0, 0.9}, std::nullopt},
                              {{0.0, 0.0, 1.1}, {nan, 0.0, 0.9}, std::nullopt}};
  const FrameReport& r = d.deform(bad);
  EXPECT_EQ(r.guards.probe_dropped, 3u);
  for (int p = 0; p < 3; ++p) EXPECT_EQ(r.contacts[p].state, ProbeState::kDropped);
  EXPECT_TRUE(same_bytes(sphere, before));
}

// Accuracy kept: where no guard acts, a frame moves every point by exactly the Kelvin field of
// its effective force (MATH.md §1, written out here independently of kernel.cpp), to float
// precision, with the carried normal still a unit vector.
TEST(Stability, AFrameNoGuardTouchesIsTheKelvinFieldOfItsForce) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  DeformSettings s = settings_for(kSphereSpacing);
  Deformer d(sphere, s);
  const Vec3 a = before.position(0), n = before.normal(0);
  const ProbeMotion m{a + n * 0.2, a - n * 0.02, std::nullopt};
  const FrameReport& r = d.deform({&m, 1});
  ASSERT_EQ(r.collisions, 1u);
  ASSERT_EQ(r.guards.total(), 0u) << "the case must be one no guard touches";
  ASSERT_EQ(d.frames().size(), 1u);
  const ContactReport& c = r.contacts[0];
  EXPECT_EQ(c.source_rule, SourceRule::kPrevious);
  const double g = s.kernel.material.shear_modulus, nu = s.kernel.material.poisson_ratio;
  const double pi = std::acos(-1.0);
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const Vec3 rv = before.position(i) - c.source;
    const double len = norm(rv);
    const Vec3 rh = rv * (1.0 / len);
    const double scale = 1.0 / (16.0 * pi * g * (1.0 - nu) * len);
    const Vec3 u = (c.effective_force * (3.0 - 4.0 * nu) + rh * dot(rh, c.effective_force)) * scale;
    worst = std::max(worst, norm(sphere.position(i) - before.position(i) - u));
    largest = std::max(largest, norm(u));
    EXPECT_NEAR(norm(sphere.normal(i)), 1.0, 1e-5);
  }
  EXPECT_LT(worst, 1e-5 * largest + 1e-7);
  EXPECT_NEAR(largest, r.max_displacement, 1e-5 * largest);
}

}  // namespace
}  // namespace sculpt::deform
