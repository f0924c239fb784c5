// Conversions between the hal's structs and the sculpt_lcm messages: exact round trips through
// the wire bytes, and every invalid field refused (false, never a throw).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "sculpt/logging/glove_messages.hpp"
#include "sculpt/logging/records.hpp"

namespace sculpt::logging {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

hal::GloveSample make_sample(hal::SampleKind kind) {
  hal::GloveSample s;
  s.hand = 1;
  s.kind = kind;
  s.sequence = 0xFFFF'FFF0u;  // above INT32_MAX: must survive the signed wire field
  s.device_time_us = 123'456'789'012ull;
  for (std::size_t j = 0; j < hal::kJointPoints; ++j) {
    for (std::size_t c = 0; c < 3; ++c) s.joints[j][c] = 0.25f * static_cast<float>(j) - 0.125f * static_cast<float>(c) + 1e-7f;
  }
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t a = 0; a < 4; ++a) s.angles[f][a] = -0.3f + 0.11f * static_cast<float>(f * 4 + a);
  }
  s.wrist.position = {0.1f, -0.2f, 0.3f};
  s.wrist.orientation = {0.5f, 0.5f, -0.5f, 0.5f};
  return s;
}

template <typename Message>
std::vector<std::uint8_t> encode(const Message& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return bytes;
}

void expect_same(const hal::GloveSample& a, const hal::GloveSample& b) {
  EXPECT_EQ(a.hand, b.hand);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.device_time_us, b.device_time_us);
  EXPECT_EQ(a.joints, b.joints);
  EXPECT_EQ(a.angles, b.angles);
  EXPECT_EQ(a.wrist.position, b.wrist.position);
  EXPECT_EQ(a.wrist.orientation, b.wrist.orientation);
}

TEST(LcmGloveMessages, GloveSampleRoundTripsThroughTheWireForBothKinds) {
  for (auto kind : {hal::SampleKind::kPositions, hal::SampleKind::kAngles}) {
    const hal::GloveSample sent = make_sample(kind);
    sculpt_lcm::glove_sample_t message{};
    to_lcm(sent, 1'700'000'000'000'000, message);
    EXPECT_EQ(message.utime, 1'700'000'000'000'000);
    const auto bytes = encode(message);
    sculpt_lcm::glove_sample_t decoded{};
    ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    hal::GloveSample received;
    ASSERT_TRUE(from_lcm(decoded, received));
    expect_same(sent, received);
    EXPECT_EQ(received.receive_time_ns, 0);  // the receiver's clock, not the wire's
  }
}

TEST(LcmGloveMessages, GloveSampleRejectsEachInvalidField) {
  sculpt_lcm::glove_sample_t good{};
  to_lcm(make_sample(hal::SampleKind::kPositions), 0, good);
  hal::GloveSample out;
  ASSERT_TRUE(from_lcm(good, out));

  auto rejects = [&](auto&& spoil) {
    sculpt_lcm::glove_sample_t m = good;
    spoil(m);
    hal::GloveSample unused;
    return !from_lcm(m, unused);
  };
  EXPECT_TRUE(rejects([](auto& m) { m.hand = 2; }));
  EXPECT_TRUE(rejects([](auto& m) { m.hand = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.kind = 0; }));
  EXPECT_TRUE(rejects([](auto& m) { m.kind = 3; }));
  EXPECT_TRUE(rejects([](auto& m) { m.device_time_us = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.position[2] = kInf; }));
  EXPECT_TRUE(rejects([](auto& m) { m.orientation[0] = kNaN; }));
  for (std::size_t j = 0; j < hal::kJointPoints; ++j) {
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_TRUE(rejects([&](auto& m) { m.joints[j][c] = kNaN; })) << j << "," << c;
    }
  }
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t a = 0; a < 4; ++a) {
      EXPECT_TRUE(rejects([&](auto& m) { m.angles[f][a] = -kInf; })) << f << "," << a;
    }
  }
  // Left hand and zero device time are valid.
  EXPECT_FALSE(rejects([](auto& m) { m.hand = 0; m.device_time_us = 0; }));
}

TEST(LcmGloveMessages, HapticCommandRoundTripsThroughTheWire) {
  hal::HapticCommand sent;
  sent.hand = 0;
  sent.tick = 0xFFFF'FFFFu;
  sent.active_mask = 0b10110;
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    sent.force[f] = {0.5f * static_cast<float>(f), -1.25f, 3e-3f * static_cast<float>(f + 1)};
  }
  sculpt_lcm::haptic_command_t message{};
  to_lcm(sent, 42, message);
  EXPECT_EQ(message.utime, 42);
  const auto bytes = encode(message);
  sculpt_lcm::haptic_command_t decoded{};
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  hal::HapticCommand received;
  ASSERT_TRUE(from_lcm(decoded, received));
  EXPECT_EQ(received.hand, sent.hand);
  EXPECT_EQ(received.tick, sent.tick);
  EXPECT_EQ(received.active_mask, sent.active_mask);
  EXPECT_EQ(received.force, sent.force);
}

TEST(LcmGloveMessages, HapticCommandRejectsEachInvalidField) {
  sculpt_lcm::haptic_command_t good{};
  to_lcm(hal::HapticCommand{}, 0, good);
  hal::HapticCommand out;
  ASSERT_TRUE(from_lcm(good, out));
  auto rejects = [&](auto&& spoil) {
    sculpt_lcm::haptic_command_t m = good;
    spoil(m);
    hal::HapticCommand unused;
    return !from_lcm(m, unused);
  };
  EXPECT_TRUE(rejects([](auto& m) { m.hand = 2; }));
  EXPECT_TRUE(rejects([](auto& m) { m.tick = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.tick = std::int64_t{1} << 32; }));
  EXPECT_TRUE(rejects([](auto& m) { m.active_mask = 0x20; }));
  EXPECT_TRUE(rejects([](auto& m) { m.active_mask = -1; }));
  EXPECT_TRUE(rejects([](auto& m) { m.force[4][2] = kNaN; }));
  EXPECT_TRUE(rejects([](auto& m) { m.force[0][0] = kInf; }));
  EXPECT_FALSE(rejects([](auto& m) { m.active_mask = 0x1F; m.hand = 1; }));
}

// What a receiver meets on the wire: every truncation and seeded corruptions of a valid
// message must either fail to decode or decode to something from_lcm accepts or refuses,
// without a crash (this test also runs under ASan + UBSan).
TEST(LcmGloveMessages, TruncatedAndCorruptedBytesNeverCrash) {
  sculpt_lcm::glove_sample_t message{};
  to_lcm(make_sample(hal::SampleKind::kAngles), 7, message);
  const auto bytes = encode(message);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    sculpt_lcm::glove_sample_t decoded{};
    EXPECT_LT(decoded.decode(bytes.data(), 0, static_cast<int>(n)), 0) << "truncated to " << n;
  }
  std::mt19937 rng(20240607);
  std::uniform_int_distribution<std::size_t> position(0, bytes.size() - 1);
  std::uniform_int_distribution<int> value(0, 255);
  int accepted = 0, refused = 0, undecodable = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    auto corrupt = bytes;
    const int flips = 1 + trial % 4;
    for (int k = 0; k < flips; ++k) corrupt[position(rng)] = static_cast<std::uint8_t>(value(rng));
    sculpt_lcm::glove_sample_t decoded{};
    if (decoded.decode(corrupt.data(), 0, static_cast<int>(corrupt.size())) < 0) {
      ++undecodable;
      continue;
    }
    hal::GloveSample out;
    if (from_lcm(decoded, out)) {
      ++accepted;
      EXPECT_LT(out.hand, hal::kHands);
    } else {
      ++refused;
    }
  }
  EXPECT_GT(undecodable, 0);  // the fingerprint caught corruptions of the first 8 bytes
  EXPECT_GT(refused + accepted, 0);
}

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
  const auto bytes = encode(message);
  sculpt_lcm::collision_event_t decoded{};
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  CollisionRecord got;
  ASSERT_TRUE(from_lcm(decoded, got));
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
