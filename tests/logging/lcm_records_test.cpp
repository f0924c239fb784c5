// The logging records and their LCM messages: exact round trips through the wire bytes, every
// field that could not be replayed refused, and the wall-clock stamp.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sculpt/logging/records.hpp"
#include "support/lcm_round_trip.hpp"

namespace sculpt::logging {
namespace {

CollisionRecord make_collision() {
  CollisionRecord r;
  r.utime = 1'700'000'000'123'456;
  r.tick = 98'765;
  r.time_s = 98.765;
  r.hand = 1;
  r.finger = 3;
  r.mode = CollisionMode::kPull;
  r.probe = {0.1, 0.2, 0.3};
  r.contact_index = 3202;
  r.contact = {0.11, 0.21, 0.31};
  r.source = {0.12, 0.22, 0.32};
  r.force = {-0.01, -0.01, -0.01};
  r.weights = {0.9, 1.1, 1.0};
  r.effective_force = {-0.009, -0.011, -0.01};
  r.bc_radius = 0.06;
  r.region_kind = RegionKind::kRadius;
  r.region_centre = {0.1, 0.2, 0.3};
  r.region_radius = 1.2;
  r.region_id = -1;
  r.kernel = KernelKind::kRegularized;
  r.kernel_eps = 0.03;
  r.shear_modulus = 3e7;
  r.poisson_ratio = 0.45;
  r.form = ForceForm::kForce;
  r.residual = 1e-9;
  r.condition = std::numeric_limits<double>::infinity();  // rank-deficient solves are real
  r.frame_id = 12;
  r.frame_size = 2;
  return r;
}

TEST(LcmRecords, CollisionEventRoundTripsThroughTheWire) {
  const CollisionRecord sent = make_collision();
  sculpt_lcm::collision_event_t message{};
  to_lcm(sent, message);
  CollisionRecord got;
  ASSERT_TRUE(test::lcm_round_trip(message, got));
  EXPECT_EQ(got.utime, sent.utime);
  EXPECT_EQ(got.tick, sent.tick);
  EXPECT_EQ(got.time_s, sent.time_s);
  EXPECT_EQ(got.hand, sent.hand);
  EXPECT_EQ(got.finger, sent.finger);
  EXPECT_EQ(got.mode, sent.mode);
  EXPECT_EQ(got.probe, sent.probe);
  EXPECT_EQ(got.contact_index, sent.contact_index);
  EXPECT_EQ(got.contact, sent.contact);
  EXPECT_EQ(got.source, sent.source);
  EXPECT_EQ(got.force, sent.force);
  EXPECT_EQ(got.weights, sent.weights);
  EXPECT_EQ(got.effective_force, sent.effective_force);
  EXPECT_EQ(got.bc_radius, sent.bc_radius);
  EXPECT_EQ(got.region_kind, sent.region_kind);
  EXPECT_EQ(got.region_centre, sent.region_centre);
  EXPECT_EQ(got.region_radius, sent.region_radius);
  EXPECT_EQ(got.region_id, sent.region_id);
  EXPECT_EQ(got.kernel, sent.kernel);
  EXPECT_EQ(got.kernel_eps, sent.kernel_eps);
  EXPECT_EQ(got.shear_modulus, sent.shear_modulus);
  EXPECT_EQ(got.poisson_ratio, sent.poisson_ratio);
  EXPECT_EQ(got.form, sent.form);
  EXPECT_EQ(got.residual, sent.residual);
  EXPECT_EQ(got.condition, sent.condition);
  EXPECT_EQ(got.frame_id, sent.frame_id);
  EXPECT_EQ(got.frame_size, sent.frame_size);
}

TEST(LcmRecords, CollisionEventRejectsWhatCouldNotBeReplayed) {
  sculpt_lcm::collision_event_t good{};
  to_lcm(make_collision(), good);
  auto rejects = [&](auto&& spoil) {
    sculpt_lcm::collision_event_t m = good;
    spoil(m);
    CollisionRecord unused;
    return !from_lcm(m, unused);
  };
  EXPECT_FALSE(rejects([](auto&) {}));
  EXPECT_TRUE(rejects([](auto& m) { m.hand = 2; }));
  EXPECT_TRUE(rejects([](auto& m) { m.finger = 5; }));
  EXPECT_TRUE(rejects([](auto& m) { m.mode = 2; }));
  EXPECT_TRUE(rejects([](auto& m) { m.region_kind = 3; }));
  EXPECT_TRUE(rejects([](auto& m) { m.kernel = 2; }));
  EXPECT_TRUE(rejects([](auto& m) { m.form = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.frame_size = 0; }));
  EXPECT_TRUE(rejects([](auto& m) { m.contact_index = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.source[1] = std::nan(""); }));
  EXPECT_TRUE(rejects([](auto& m) { m.effective_force[0] = HUGE_VAL; }));
  EXPECT_TRUE(rejects([](auto& m) { m.shear_modulus = std::nan(""); }));
}

TEST(LcmRecords, FingertipAndTickCopyEveryField) {
  FingertipRecord f;
  f.utime = 5;
  f.tick = 6;
  f.hand = 1;
  f.finger = 4;
  f.raw = {1, 2, 3};
  f.filtered = {4, 5, 6};
  f.registered = {7, 8, 9};
  f.accepted = true;
  f.in_contact = false;
  sculpt_lcm::fingertip_state_t fm{};
  to_lcm(f, fm);
  EXPECT_EQ(fm.utime, 5);
  EXPECT_EQ(fm.tick, 6);
  EXPECT_EQ(fm.hand, 1);
  EXPECT_EQ(fm.finger, 4);
  EXPECT_EQ(fm.raw[2], 3.0f);
  EXPECT_EQ(fm.filtered[0], 4.0f);
  EXPECT_EQ(fm.registered[1], 8.0f);
  EXPECT_EQ(fm.accepted, 1);
  EXPECT_EQ(fm.in_contact, 0);

  TickRecord t;
  t.utime = 1;
  t.tick = 2;
  t.tick_time_us = 312.5f;
  t.budget_us = 1000.0f;
  t.overruns = 3;
  t.missed_periods = 4;
  t.region_points = 54'559;
  t.collisions = 5;
  t.glove_state = sculpt_lcm::tick_stats_t::GLOVE_STALE;
  t.glove_age_ms = 12.5f;
  sculpt_lcm::tick_stats_t tm{};
  to_lcm(t, tm);
  EXPECT_EQ(tm.tick_time_us, 312.5f);
  EXPECT_EQ(tm.budget_us, 1000.0f);
  EXPECT_EQ(tm.overruns, 3);
  EXPECT_EQ(tm.missed_periods, 4);
  EXPECT_EQ(tm.region_points, 54'559);
  EXPECT_EQ(tm.collisions, 5);
  EXPECT_EQ(tm.glove_state, sculpt_lcm::tick_stats_t::GLOVE_STALE);
  EXPECT_EQ(tm.glove_age_ms, 12.5f);
}

TEST(LcmRecords, WallTimeIsMicrosecondsSinceTheEpoch) {
  const std::int64_t t = wall_time_us();
  EXPECT_GT(t, std::int64_t{1'600'000'000} * 1'000'000);  // after 2020
  EXPECT_LT(t, std::int64_t{4'000'000'000} * 1'000'000);
}

}  // namespace
}  // namespace sculpt::logging
