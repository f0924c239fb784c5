// Conversions between the hal's structs and the sculpt_lcm messages: exact round trips through
// the wire bytes, and every invalid field refused (false, never a throw).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "sculpt/hal/lcm_messages.hpp"
#include "support/lcm_round_trip.hpp"

namespace sculpt::hal {
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
    for (std::size_t c = 0; c < 3; ++c)
      s.joints[j][c] = 0.25f * static_cast<float>(j) - 0.125f * static_cast<float>(c) + 1e-7f;
  }
  for (std::size_t f = 0; f < hal::kFingers; ++f) {
    for (std::size_t a = 0; a < 4; ++a) s.angles[f][a] = -0.3f + 0.11f * static_cast<float>(f * 4 + a);
  }
  s.wrist.position = {0.1f, -0.2f, 0.3f};
  s.wrist.orientation = {0.5f, 0.5f, -0.5f, 0.5f};
  return s;
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
    hal::GloveSample received;
    ASSERT_TRUE(test::lcm_round_trip(message, received));
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
  EXPECT_FALSE(rejects([](auto& m) {
    m.hand = 0;
    m.device_time_us = 0;
  }));
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
  hal::HapticCommand received;
  ASSERT_TRUE(test::lcm_round_trip(message, received));
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
  EXPECT_FALSE(rejects([](auto& m) {
    m.active_mask = 0x1F;
    m.hand = 1;
  }));
}

// What a receiver meets on the wire: every truncation and seeded corruptions of a valid
// message must either fail to decode or decode to something from_lcm accepts or refuses,
// without a crash (this test also runs under ASan + UBSan).
TEST(LcmGloveMessages, TruncatedAndCorruptedBytesNeverCrash) {
  sculpt_lcm::glove_sample_t message{};
  to_lcm(make_sample(hal::SampleKind::kAngles), 7, message);
  const auto bytes = test::lcm_encode(message);
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

}  // namespace
}  // namespace sculpt::hal
