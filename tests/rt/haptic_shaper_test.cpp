// What may reach the hand: clamp, slew limit on rising force along every direction, release at
// once, never a non-finite command; and the station sends a bounded command every tick of a
// contact.
#include "sculpt/rt/haptic_shaper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace sculpt::rt {
namespace {

using deform::Vec3;

TEST(HapticShaper, ClampsRisesAtTheRateLimitAndFallsAtOnce) {
  HapticLimits l;
  l.gain = 2.0;
  l.max_force = 4.0;
  l.max_force_rate = 100.0;  // N/s: 0.1 N per tick at 1 kHz
  HapticShaper s(l, 1, 1000.0);
  const Vec3 huge{0.0, 0.0, 5e5};  // the unit sphere's raw resultant before units and limits
  double previous = 0.0;
  for (int t = 1; t <= 60; ++t) {
    const double f = deform::norm(s.step(0, huge));
    EXPECT_LE(f, 4.0 + 1e-12);
    EXPECT_LE(f - previous, 0.1 + 1e-12) << "tick " << t;
    EXPECT_NEAR(f, std::min(4.0, 0.1 * t), 1e-9) << "tick " << t;
    previous = f;
  }
  // A smaller target is taken in the same tick (falling force is never delayed).
  EXPECT_NEAR(deform::norm(s.step(0, {0.0, 0.0, 0.5})), 1.0, 1e-12);  // gain 2
  s.release(0);
  EXPECT_EQ(deform::norm(s.step(0, {})), 0.0);
}

// A reversal at full force was an 8 N step on the hand while the magnitude alone was limited.
TEST(HapticShaper, AReversalFallsToNothingAtOnceAndRisesAgainAtTheRateLimit) {
  HapticLimits l;
  l.max_force = 4.0;
  l.max_force_rate = 200.0;  // 0.2 N per tick at 1 kHz
  HapticShaper s(l, 1, 1000.0);
  for (int t = 0; t < 40; ++t) s.step(0, {4.0, 0.0, 0.0});
  ASSERT_NEAR(s.step(0, {4.0, 0.0, 0.0}).x, 4.0, 1e-12);
  for (int t = 1; t <= 25; ++t) {
    const Vec3 out = s.step(0, {-4.0, 0.0, 0.0});
    EXPECT_NEAR(out.x, -std::min(4.0, 0.2 * t), 1e-9) << "tick " << t;
    EXPECT_EQ(out.y, 0.0);
    EXPECT_EQ(out.z, 0.0);
  }
}

// Whatever the targets do (turn, reverse, grow past the clamp, shrink), for every direction d
// the push along d rises by at most the limit a tick over what it was, or over zero; the push
// along where the output pointed falls at once to the target's; the output never exceeds the
// clamp; and a target that stays put is reached.
TEST(HapticShaper, NoDirectionsPushRisesFasterThanTheLimitAndFallsAreImmediate) {
  HapticLimits l;
  l.gain = 1.5;
  l.max_force = 4.0;
  l.max_force_rate = 300.0;  // 0.3 N per tick at 1 kHz
  const double rise = 0.3;
  HapticShaper s(l, 1, 1000.0);
  std::mt19937 random(20261207);
  std::uniform_real_distribution<double> component(-4.0, 4.0);
  const auto random_vector = [&] { return Vec3{component(random), component(random), component(random)}; };
  std::vector<Vec3> directions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  for (int k = 0; k < 50; ++k) directions.push_back(deform::normalized(random_vector()));
  Vec3 previous{};
  for (int t = 0; t < 3000; ++t) {
    // Thirty ticks of a new random target every tick (turns, reversals, past the clamp), then
    // twenty of one direction growing in steps and dropping to nothing every seventh tick.
    const Vec3 reaction = t % 50 < 30 ? random_vector() * 0.8 : Vec3{0.7, -0.4, 0.2} * static_cast<double>(t % 7);
    Vec3 target = reaction * l.gain;
    if (deform::norm(target) > l.max_force) target = target * (l.max_force / deform::norm(target));
    const Vec3 out = s.step(0, reaction);
    EXPECT_LE(deform::norm(out), l.max_force + 1e-12) << "tick " << t;
    for (const Vec3& d : directions) {
      EXPECT_LE(deform::dot(out, d), std::max(0.0, deform::dot(previous, d)) + rise + 1e-9) << "tick " << t;
    }
    const Vec3 target_direction = deform::norm(target) > 0.0 ? deform::normalized(target) : Vec3{};
    EXPECT_LE(deform::dot(out, target_direction), std::max(0.0, deform::dot(previous, target_direction)) + rise + 1e-9);
    if (deform::norm(previous) > 0.0) {
      const Vec3 was = deform::normalized(previous);
      const double wanted_along = deform::dot(target, was);
      if (wanted_along <= deform::norm(previous)) {
        EXPECT_LE(deform::dot(out, was), std::max(0.0, wanted_along) + 1e-9) << "tick " << t;
      }
    }
    previous = out;
  }
  // Held long enough (from any output within the clamp, at most 8 N to cover at 0.3 N a tick),
  // a target is reached exactly.
  const Vec3 held{-1.0, 2.0, 0.5};
  Vec3 out{};
  for (int t = 0; t < 30; ++t) out = s.step(0, held);
  EXPECT_EQ(out.x, held.x * l.gain);
  EXPECT_EQ(out.y, held.y * l.gain);
  EXPECT_EQ(out.z, held.z * l.gain);
}

TEST(HapticShaper, NonFiniteReactionSendsNothing) {
  HapticShaper s({}, 1, 1000.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3 out = s.step(0, {nan, 0.0, std::numeric_limits<double>::infinity()});
  EXPECT_TRUE(deform::is_finite(out));
  EXPECT_EQ(deform::norm(out), 0.0);
}

TEST(HapticShaper, RefusesLimitsThatAreNotSafe) {
  HapticLimits l;
  l.max_force = 0.0;
  EXPECT_THROW(l.validate(), std::invalid_argument);
  l = {};
  l.max_force_rate = std::numeric_limits<double>::infinity();
  EXPECT_THROW(l.validate(), std::invalid_argument);
  l = {};
  l.gain = -1.0;
  EXPECT_THROW(l.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::rt
