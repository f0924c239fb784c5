// Whole collision frames against physical expectations: the surface follows the probe and
// never swallows it, superposition holds, the region leaves everything else untouched.
#include "sculpt/deform/deformer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/kernel.hpp"

namespace sculpt::deform {
namespace {

DeformSettings sphere_settings() {
  DeformSettings s;
  s.kernel = {KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  s.contact.bc_radius = 0.08;
  s.contact.min_source_distance = 0.01;
  s.contact.guard_distance = 0.1;
  return s;
}

Vec3 pole_probe(double height) { return {0.0, 0.0, height}; }

// The direction of the lattice point nearest to `approximate`, so that a probe placed along it
// has that point exactly below it.
Vec3 lattice_direction(const PointModel& m, const Vec3& approximate) {
  const Vec3 d = normalized(approximate);
  std::size_t best = 0;
  for (std::size_t i = 1; i < m.size(); ++i)
    if (dot(m.position(i), d) > dot(m.position(best), d)) best = i;
  return normalized(m.position(best));
}

TEST(Deformer, SinglePushMovesTheContactOntoTheProbeWhichStaysOutside) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  const Vec3 d = lattice_direction(sphere, {0.0, 0.0, 1.0});
  Deformer deformer(sphere, sphere_settings());
  const ProbeMotion push{d * 1.1, d * 0.95, std::nullopt};
  const FrameReport& r = deformer.deform({&push, 1});
  ASSERT_EQ(r.collisions, 1u);
  const ContactReport& c = r.contacts[0];
  ASSERT_EQ(c.state, ProbeState::kCollided);
  ASSERT_TRUE(r.solve.ok);
  ASSERT_GT(c.boundary_points, 1u);
  const double depth = norm(c.force);
  EXPECT_NEAR(depth, 0.05, 1e-6);
  // Its neighbours within eps all ask for the same motion F, which a single Kelvin source meets
  // only in the mean: the field at the ring (lattice pitch p ~ 0.063 off A) is h / sqrt(h^2 +
  // p^2) ~ 0.85 of that at A for a source h = 0.1 above, so A may miss by that spread.
  EXPECT_LT(norm(sphere.position(c.nearest) - push.current), 0.25 * depth);
  Vec3 mean;
  std::size_t ring = 0;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    if (norm(before.position(i) - c.contact) > deformer.settings().contact.bc_radius) continue;
    mean += sphere.position(i) - before.position(i);
    ++ring;
  }
  ASSERT_EQ(ring, c.boundary_points);
  mean *= 1.0 / static_cast<double>(ring);
  EXPECT_LT(norm(mean - c.force), 0.1 * depth);
  EXPECT_GE(c.side_after, -1e-3 * depth);  // on or outside the deformed surface
  EXPECT_FALSE(c.pushed_out);
  EXPECT_LT(r.solve.relative_residual, 0.3);
  EXPECT_GT(r.solve.condition, 0.0);
}

// With eps below the lattice pitch the neighbourhood is A alone, and A lands on the probe.
TEST(Deformer, SinglePointNeighbourhoodLandsExactlyOnTheProbe) {
  PointModel sphere = make_sphere();
  DeformSettings s = sphere_settings();
  s.contact.bc_radius = 0.03;
  const Vec3 d = lattice_direction(sphere, {0.3, 0.2, 1.0});
  Deformer deformer(sphere, s);
  const ProbeMotion push{d * 1.1, d * 0.93, std::nullopt};
  const FrameReport& r = deformer.deform({&push, 1});
  ASSERT_EQ(r.contacts[0].boundary_points, 1u);
  EXPECT_LT(norm(sphere.position(r.contacts[0].nearest) - push.current), 1e-5);
  EXPECT_LT(r.solve.relative_residual, 1e-6);
  EXPECT_GE(r.contacts[0].side_after, -1e-6);  // on the surface, to float rounding
}

TEST(Deformer, PullMirrorsThePush) {
  PointModel sphere = make_sphere();
  DeformSettings s = sphere_settings();
  s.contact.mode = ContactMode::kPull;
  Deformer deformer(sphere, s);
  const Vec3 d = lattice_direction(sphere, {0.0, 0.0, 1.0});
  const ProbeMotion pull{d * 0.9, d * 1.05, std::nullopt};
  const FrameReport& r = deformer.deform({&pull, 1});
  ASSERT_EQ(r.collisions, 1u);
  const ContactReport& c = r.contacts[0];
  const double depth = norm(c.force);
  EXPECT_NEAR(dot(c.force, d), 0.05, 1e-6);
  EXPECT_LT(norm(sphere.position(c.nearest) - pull.current), 0.25 * depth);
  EXPECT_LE(c.side_after, 1e-3 * depth);  // still inside or on the surface
}

// Linear superposition: the jointly solved frame moves every point by the sum of what each
// effective force does alone.
TEST(Deformer, JointFrameIsTheSumOfItsEffectiveForcesApplyAlone) {
  const PointModel original = make_sphere();
  PointModel joint = original;
  Deformer deformer(joint, sphere_settings());
  const ProbeMotion probes[2] = {{pole_probe(1.1), pole_probe(0.94), std::nullopt},
                                 {{1.1, 0.0, 0.0}, {0.95, 0.0, 0.0}, std::nullopt}};
  const FrameReport& r = deformer.deform(probes);
  ASSERT_EQ(r.collisions, 2u);
  PointModel summed = original;
  for (const ContactReport& c : r.contacts) {
    if (c.state != ProbeState::kCollided) continue;
    PointModel alone = original;
    const SourceForce f{c.source, c.effective_force};
    (void)apply_displacements(alone, deformer.settings().kernel, {&f, 1}, {}, true, {Precision::kDouble, false});
    for (std::size_t i = 0; i < original.size(); ++i) {
      summed.set_position(i, summed.position(i) + (alone.position(i) - original.position(i)));
    }
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    worst = std::max(worst, norm(summed.position(i) - joint.position(i)));
  }
  EXPECT_LT(worst, 1e-5);
}

// Two fingers on opposite sides hardly see each other: solving them jointly gives each nearly
// the force it gets alone (the cross-talk is the Kelvin field across the sphere, ~1/R).
TEST(Deformer, FarApartFingersSolvedJointlyMatchEachAlone) {
  const ProbeMotion a{pole_probe(1.1), pole_probe(0.95), std::nullopt};
  const ProbeMotion b{pole_probe(-1.1), pole_probe(-0.95), std::nullopt};
  PointModel m1 = make_sphere(), m2 = make_sphere(), mj = make_sphere();
  Deformer d1(m1, sphere_settings()), d2(m2, sphere_settings()), dj(mj, sphere_settings());
  const Vec3 fa = d1.deform({&a, 1}).contacts[0].effective_force;
  const Vec3 fb = d2.deform({&b, 1}).contacts[0].effective_force;
  const ProbeMotion both[2] = {a, b};
  const FrameReport& r = dj.deform(both);
  // Cross-talk bound: each source sits h ~ 0.1 off its contact and 2 from the other contact,
  // so the other finger's field there is ~h/2 = 5 % of its own; allow twice that.
  EXPECT_LT(norm(r.contacts[0].effective_force - fa), 0.1 * norm(fa));
  EXPECT_LT(norm(r.contacts[1].effective_force - fb), 0.1 * norm(fb));
  // and the model moves as the two separate edits added together, to the same bound
  const PointModel original = make_sphere();
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    const Vec3 sum = (m1.position(i) - original.position(i)) + (m2.position(i) - original.position(i));
    worst = std::max(worst, norm(mj.position(i) - original.position(i) - sum));
    scale = std::max(scale, norm(sum));
  }
  EXPECT_LT(worst, 0.1 * scale);
}

struct RegionOutcome {
  double band_ratio;
  double band_displacement;
  double contact_miss;  // |A after - probe| / depth
  std::size_t points, band;
};

RegionOutcome press_in_region(double radius, double border_weight, bool check_outside) {
  const PointModel original = make_sphere();
  PointModel model = original;
  DeformSettings s = sphere_settings();
  s.region.kind = RegionSettings::Kind::kRadius;
  s.region.radius = radius;
  s.region.border_weight = border_weight;
  s.contact.bc_radius = 0.03;  // A alone, so the contact's miss is the band's doing
  Deformer deformer(model, s);
  const Vec3 d = lattice_direction(model, {0.0, 0.0, 1.0});
  const ProbeMotion push{d * 1.1, d * 0.95, std::nullopt};
  const FrameReport& r = deformer.deform({&push, 1});
  EXPECT_EQ(r.collisions, 1u);
  EXPECT_GT(r.border_points, 0u);
  const Vec3 centre = r.contacts[0].contact;
  std::size_t inside = 0;
  for (std::size_t i = 0; i < original.size() && check_outside; ++i) {
    if (norm(original.position(i) - centre) <= radius) {
      ++inside;
      continue;
    }
    const bool same = std::memcmp(&original.x[i], &model.x[i], sizeof(float)) == 0 &&
                      std::memcmp(&original.y[i], &model.y[i], sizeof(float)) == 0 &&
                      std::memcmp(&original.z[i], &model.z[i], sizeof(float)) == 0 &&
                      std::memcmp(&original.nx[i], &model.nx[i], sizeof(float)) == 0 &&
                      std::memcmp(&original.ny[i], &model.ny[i], sizeof(float)) == 0 &&
                      std::memcmp(&original.nz[i], &model.nz[i], sizeof(float)) == 0;
    EXPECT_TRUE(same) << "point " << i << " outside the region moved";
  }
  if (check_outside) {
    EXPECT_EQ(r.region_points, inside);
  }
  return {r.max_border_displacement / r.max_contact_displacement, r.max_border_displacement,
          norm(model.position(r.contacts[0].nearest) - push.current) / norm(r.contacts[0].force), r.region_points,
          r.border_points};
}

TEST(Deformer, RegionLeavesOutsidePointsBitIdenticalAndBoundsTheBand) {
  const double radius = 0.6;
  const RegionOutcome plain = press_in_region(radius, 1.0, true);
  const RegionOutcome firm = press_in_region(radius, 10.0, false);
  std::printf(
      "[ region ] radius %.2f: %zu points, band %zu; band/contact displacement %.4f "
      "(border weight 1), %.4f (weight 10); contact miss %.3f / %.3f of depth\n",
      radius, plain.points, plain.band, plain.band_ratio, firm.band_ratio, plain.contact_miss, firm.contact_miss);
  // Bound: the Kelvin field decays as 1/R, so the band, at least R - w ~ 0.57 from the contact,
  // sees at most ~h / (R - w) ~ 0.1 / 0.57 of what a source h ~ 0.1 above the contact gives it.
  EXPECT_LT(plain.band_ratio, 0.1 / (radius - 0.03) * 1.2);
  // One source has one shape: pinning harder cannot bend it, only scale it down. The band moves
  // less in absolute terms, and the contact pays for it.
  EXPECT_LT(firm.band_displacement, 0.5 * plain.band_displacement);
  EXPECT_NEAR(firm.band_ratio, plain.band_ratio, 0.05 * plain.band_ratio);
  EXPECT_GT(firm.contact_miss, 0.3);
  EXPECT_LT(plain.contact_miss, 0.05);
}

// Δr (thesis 4.3.2.1): a finger hovering within Δr pins its surface point with u0 = 0, which
// holds it back compared with the same frame without that finger; and a free finger that an
// extreme edit leaves inside is moved out, Δd off the surface.
TEST(Deformer, GuardedFingerHoldsItsSurfaceAndAnyFingerLeftInsideIsMovedOut) {
  DeformSettings s = sphere_settings();
  s.contact.guard_distance = 0.002;
  PointModel guarded_model = make_sphere();
  const PointModel before = guarded_model;
  const Vec3 top = lattice_direction(before, {0.0, 0.0, 1.0});
  const Vec3 east = lattice_direction(before, {1.0, 0.0, 0.0});
  const Vec3 west = lattice_direction(before, {-1.0, 0.0, 0.0});
  // An extreme press at the pole bulges the equator outward (u_x = gamma (r.f) x / R^3 > 0 for
  // a force along -z), toward both hovering fingers.
  const ProbeMotion press{top * 1.1, top * 0.6, std::nullopt};
  const ProbeMotion probes[3] = {press,
                                 {east * 1.001, east * 1.001, std::nullopt},   // within Δr
                                 {west * 1.004, west * 1.004, std::nullopt}};  // beyond Δr
  Deformer guarded(guarded_model, s);
  const FrameReport& r = guarded.deform(probes);
  ASSERT_EQ(r.contacts[0].state, ProbeState::kCollided);
  ASSERT_EQ(r.contacts[1].state, ProbeState::kGuarded);
  ASSERT_GT(r.contacts[1].boundary_points, 0u);
  ASSERT_EQ(r.contacts[2].state, ProbeState::kFree);

  PointModel alone_model = make_sphere();
  Deformer alone(alone_model, s);
  alone.deform({&press, 1});
  const std::uint32_t e = r.contacts[1].nearest;
  const double held = dot(guarded_model.position(e) - before.position(e), east);
  const double free = dot(alone_model.position(e) - before.position(e), east);
  EXPECT_GT(free, 0.004);
  EXPECT_LT(held, free);

  const std::uint32_t w = r.contacts[2].nearest;
  EXPECT_GT(dot(guarded_model.position(w) - before.position(w), west), 0.004);
  for (int p : {1, 2}) {
    const ContactReport& c = r.contacts[p];
    EXPECT_GE(c.side_after, 0.0) << "finger " << p;
    if (!c.pushed_out) continue;
    const SurfaceSide now = locate(guarded_model, guarded.index(), guarded.drift(), c.probe_after, s.contact);
    EXPECT_NEAR(now.distance, s.contact.min_source_distance, 1e-6) << "finger " << p;
  }
  EXPECT_TRUE(r.contacts[2].pushed_out);
}

TEST(Deformer, ProbeThatStartedInsideExertsNoForce) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer deformer(sphere, sphere_settings());
  const ProbeMotion inside{pole_probe(0.9), pole_probe(0.8), std::nullopt};
  const FrameReport& r = deformer.deform({&inside, 1});
  EXPECT_EQ(r.collisions, 0u);
  EXPECT_EQ(r.contacts[0].state, ProbeState::kStartedInside);
  EXPECT_EQ(sphere.x, before.x);
}

TEST(Deformer, NoCollisionMovesNothing) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer deformer(sphere, sphere_settings());
  const ProbeMotion away{pole_probe(1.5), pole_probe(1.3), std::nullopt};
  const FrameReport& r = deformer.deform({&away, 1});
  EXPECT_EQ(r.collisions, 0u);
  EXPECT_EQ(r.contacts[0].state, ProbeState::kFree);
  EXPECT_EQ(sphere.z, before.z);
}

// Normals carried by F^-T must be perpendicular to the deformed surface, which the test
// measures from the deformed grid itself (cross product of neighbour differences).
TEST(Deformer, CarriedNormalsArePerpendicularToTheDeformedSurface) {
  const std::size_t side = 81;
  const double pitch = 0.025;
  PointModel plane = make_plane_patch(side, pitch);
  DeformSettings s = sphere_settings();
  s.contact.bc_radius = 0.03;
  Deformer deformer(plane, s);
  const ProbeMotion push{{0.0, 0.0, 0.1}, {0.0, 0.0, -0.08}, std::nullopt};
  ASSERT_EQ(deformer.deform({&push, 1}).collisions, 1u);
  double worst = 0.0;
  for (std::size_t r = 2; r + 2 < side; ++r) {
    for (std::size_t c = 2; c + 2 < side; ++c) {
      const std::size_t i = r * side + c;
      const Vec3 q = plane.position(i);
      if (norm(Vec3{q.x, q.y, 0.0}) < 0.15) continue;  // the bc patch itself is not smooth
      const Vec3 du = plane.position(i + 1) - plane.position(i - 1);
      const Vec3 dv = plane.position(i + side) - plane.position(i - side);
      const Vec3 geometric = normalized(cross(du, dv));
      const double angle = std::acos(std::min(1.0, std::abs(dot(geometric, plane.normal(i)))));
      worst = std::max(worst, angle);
    }
  }
  EXPECT_LT(worst, 0.02) << "radians";
}

TEST(Deformer, FloatAndDoubleLoopsAgree) {
  PointModel a = make_sphere(), b = make_sphere();
  DeformSettings s = sphere_settings();
  Deformer da(a, s);
  s.field.precision = Precision::kDouble;
  Deformer db(b, s);
  const ProbeMotion push{pole_probe(1.1), pole_probe(0.9), std::nullopt};
  da.deform({&push, 1});
  db.deform({&push, 1});
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LT(norm(a.position(i) - b.position(i)), 1e-6);
}

// With the displacements prescribed, G cancels: the solved forces scale with G and the kernel
// with 1/G, so a press moves the points alike at either end of the accepted range
// (kMinShearModulus, kMaxShearModulus) as at the thesis's 3e7, in the float loop too; past
// either end the forces leave the range the float loop carries.
TEST(Deformer, APressMovesThePointsAlikeForEveryAcceptedShearModulus) {
  const ProbeMotion push{pole_probe(1.1), pole_probe(0.9), std::nullopt};
  PointModel reference = make_sphere();
  Deformer(reference, sphere_settings()).deform({&push, 1});
  const PointModel base = make_sphere();
  double moved = 0.0;
  for (std::size_t i = 0; i < base.size(); ++i) moved = std::max(moved, norm(reference.position(i) - base.position(i)));
  ASSERT_GT(moved, 0.1);
  for (const double g : {kMinShearModulus, 1.0, kMaxShearModulus}) {
    PointModel m = make_sphere();
    DeformSettings s = sphere_settings();
    s.kernel.material.shear_modulus = g;
    Deformer deformer(m, s);  // it owns the report deform() returns
    EXPECT_EQ(deformer.deform({&push, 1}).collisions, 1u) << g;
    double worst = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) worst = std::max(worst, norm(m.position(i) - reference.position(i)));
    EXPECT_LT(worst, 1e-5 * moved) << "G = " << g;
  }
}

// Kelvin's point force compresses the material ahead of it: at the contact, straight ahead of
// the source, sigma n . n < 0 for a push (source outside, force inward) and for a pull (source
// inside, force outward) alike. And traction is linear in the press depth.
TEST(Deformer, TractionAheadOfTheSourceIsCompressiveAndLinearInDepth) {
  for (ContactMode mode : {ContactMode::kPush, ContactMode::kPull}) {
    DeformSettings s = sphere_settings();
    s.traction = true;
    s.contact.mode = mode;
    s.contact.bc_radius = 0.03;
    Vec3 traction[2], resultant[2];
    for (int k = 0; k < 2; ++k) {
      PointModel sphere = make_sphere();
      const Vec3 d = lattice_direction(sphere, {0.0, 0.0, 1.0});
      const double depth = 0.02 * (k + 1);
      const ProbeMotion probe = mode == ContactMode::kPush ? ProbeMotion{d * 1.1, d * (1.0 - depth), std::nullopt}
                                                           : ProbeMotion{d * 0.9, d * (1.0 + depth), std::nullopt};
      Deformer deformer(sphere, s);
      const ContactReport& c = deformer.deform({&probe, 1}).contacts[0];
      ASSERT_TRUE(c.has_traction);
      EXPECT_LT(dot(c.traction, d), 0.0);  // d is the outward normal there
      EXPECT_LT(dot(c.traction_resultant, d), 0.0);
      traction[k] = c.traction;
      resultant[k] = c.traction_resultant;
    }
    EXPECT_LT(norm(traction[1] - traction[0] * 2.0), 1e-6 * norm(traction[1]));
    EXPECT_LT(norm(resultant[1] - resultant[0] * 2.0), 1e-6 * norm(resultant[1]));
  }
}

// An explicit index set: exactly those points move, and its rim (points with an outside
// neighbour within the band width) is the pinned band.
TEST(Deformer, IndexSetRegionMovesOnlyItsPoints) {
  const PointModel original = make_sphere();
  PointModel model = original;
  DeformSettings s = sphere_settings();
  s.region.kind = RegionSettings::Kind::kIndices;
  for (std::uint32_t i = 0; i < original.size(); ++i)
    if (original.z[i] > 0.6f) s.region.indices.push_back(i);
  Deformer deformer(model, s);
  const Vec3 d = lattice_direction(model, {0.0, 0.0, 1.0});
  const ProbeMotion push{d * 1.1, d * 0.95, std::nullopt};
  const FrameReport& r = deformer.deform({&push, 1});
  ASSERT_EQ(r.collisions, 1u);
  EXPECT_EQ(r.region_points, s.region.indices.size());
  EXPECT_GT(r.border_points, 0u);
  for (std::size_t i = 0; i < original.size(); ++i) {
    const bool member = original.z[i] > 0.6f;
    const bool moved = original.x[i] != model.x[i] || original.y[i] != model.y[i] || original.z[i] != model.z[i];
    if (!member) {
      EXPECT_FALSE(moved) << i;
    }
  }
  // The band lies on the rim: every band point is within one band width of z = 0.6's circle.
  for (std::uint32_t i : deformer.region_border())
    EXPECT_LT(original.z[i], 0.6f + 1.01f * static_cast<float>(s.contact.bc_radius) + 0.02f) << i;
}

TEST(Deformer, RestoreUndoesEveryFrame) {
  const PointModel original = make_sphere();
  PointModel model = original;
  Deformer deformer(model, sphere_settings());
  const ProbeMotion push{pole_probe(1.1), pole_probe(0.9), std::nullopt};
  deformer.deform({&push, 1});
  ASSERT_GT(deformer.drift(), 0.0);
  deformer.restore(original);
  EXPECT_EQ(model.x, original.x);
  EXPECT_EQ(model.nz, original.nz);
  EXPECT_EQ(deformer.drift(), 0.0);
  deformer.rebuild_index();
  deformer.deform({&push, 1});
  deformer.restore(original);
  EXPECT_EQ(model.z, original.z);
  EXPECT_EQ(deformer.drift(), 0.0);
}

TEST(Deformer, TheDriftBoundsEveryStoredMoveWithItsRounding) {
  // The index's queries are exact only while the drift bounds how far any point moved. Far from
  // the origin a float position is coarse (at x = 4096 an ulp is 4.9e-4, a hundredth of this
  // sphere's spacing), so a stored move differs from the computed displacement by up to half
  // an ulp per coordinate: the drift must include it, press after press.
  PointModel original = make_sphere();
  for (float& x : original.x) x += 4096.0f;
  PointModel model = original;
  Deformer deformer(model, sphere_settings());
  int frames = 0;
  for (const double depth : {0.93, 0.91, 0.89, 0.87, 0.85}) {
    deformer.restore(original);
    const ProbeMotion push{pole_probe(1.1) + Vec3{4096.0, 0.0, 0.0}, pole_probe(depth) + Vec3{4096.0, 0.0, 0.0},
                           std::nullopt};
    if (deformer.deform({&push, 1}).collisions == 0) continue;
    ++frames;
    double moved = 0.0;
    for (std::size_t i = 0; i < model.size(); ++i)
      moved = std::max(moved, norm(model.position(i) - original.position(i)));
    ASSERT_GT(moved, 0.01);
    EXPECT_GE(deformer.drift(), moved) << "press to " << depth;
    EXPECT_LT(deformer.drift(), moved * 1.01 + 1e-3) << "the rounding's share stays an ulp's size";
  }
  EXPECT_EQ(frames, 5);
}

TEST(Deformer, BadSettingsAreRejectedAtConstruction) {
  PointModel sphere = make_sphere();
  DeformSettings s = sphere_settings();
  s.region.kind = RegionSettings::Kind::kRadius;
  s.region.radius = 0.1;  // smaller than bc radius + band
  EXPECT_THROW(Deformer(sphere, s), std::invalid_argument);
  PointModel bare = make_sphere();
  bare.clear_normals();
  EXPECT_THROW(Deformer(bare, sphere_settings()), std::invalid_argument);
  s = sphere_settings();
  s.kernel.kind = KernelKind::kRegularized;
  EXPECT_THROW(Deformer(sphere, s), std::invalid_argument);
}

TEST(Deformer, LeavingOutTheExtremesChangesNothingButTheirReport) {
  // The station turns the diagnostic off: the frame must move the same bytes either way.
  auto press = [](bool measure) {
    PointModel model = make_sphere();
    DeformSettings s = sphere_settings();
    s.region.kind = RegionSettings::Kind::kRadius;
    s.region.radius = 0.6;
    s.measure_extremes = measure;
    Deformer deformer(model, s);
    const Vec3 d = lattice_direction(model, {0.0, 0.0, 1.0});
    const ProbeMotion push{d * 1.1, d * 0.95, std::nullopt};
    const FrameReport r = deformer.deform({&push, 1});
    return std::make_pair(model, r);
  };
  const auto [measured, measured_report] = press(true);
  const auto [plain, plain_report] = press(false);
  ASSERT_EQ(measured_report.collisions, 1u);
  ASSERT_GT(measured_report.border_points, 0u);
  EXPECT_GT(measured_report.max_contact_displacement, 0.0);
  EXPECT_GT(measured_report.max_border_displacement, 0.0);
  EXPECT_EQ(plain_report.max_contact_displacement, 0.0);
  EXPECT_EQ(plain_report.max_border_displacement, 0.0);
  EXPECT_EQ(plain_report.region_points, measured_report.region_points);
  EXPECT_EQ(std::memcmp(plain.x.data(), measured.x.data(), plain.x.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(plain.y.data(), measured.y.data(), plain.y.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(plain.z.data(), measured.z.data(), plain.z.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(plain.nz.data(), measured.nz.data(), plain.nz.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace sculpt::deform
