// What may reach the hand: clamp, slew limit on rising force, release at once, never a
// non-finite command; and the station sends a bounded command every tick of a contact.
#include "sculpt/rt/haptic_shaper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

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
