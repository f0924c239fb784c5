// SimScript: validation messages, interpolation against hand-computed values, the joint
// layout, ordering and timing of the stream, jitter statistics, dropouts as sequence gaps.

#include "sculpt/hal/sim_script.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace sculpt::hal {
namespace {

SimConfig one_finger(double rate_hz, std::vector<Keyframe> keys, std::uint8_t hand = 0, std::uint8_t finger = 1) {
  SimConfig c;
  c.rate_hz = rate_hz;
  c.fingers.push_back(FingerScript{hand, finger, std::move(keys)});
  return c;
}

std::string error_of(const SimConfig& c) {
  try {
    SimScript s(c);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<GloveSample> all(SimScript& s, std::size_t limit = 1'000'000) {
  std::vector<GloveSample> out;
  GloveSample g;
  while (out.size() < limit && s.next(g)) out.push_back(g);
  return out;
}

TEST(SimScript, RejectsInvalidFieldsNamingThem) {
  SimConfig c = one_finger(80, {{0, 0, 0, 0}});
  c.rate_hz = 0;
  EXPECT_EQ(error_of(c), "glove.sim.rate_hz: 0 is outside 1..10000 Hz");
  c.rate_hz = 10001;
  EXPECT_NE(error_of(c).find("glove.sim.rate_hz"), std::string::npos);
  c.rate_hz = 80;
  c.dropout_probability = 1.5;
  EXPECT_NE(error_of(c).find("glove.sim.dropout_probability"), std::string::npos);
  c.dropout_probability = 0;
  c.jitter_stddev = -1;
  EXPECT_NE(error_of(c).find("glove.sim.jitter_stddev"), std::string::npos);

  SimConfig b;
  b.fingers.push_back(FingerScript{0, 1, {{0, 0, 0, 0}}});
  b.fingers.push_back(FingerScript{0, 2, {{0, 0, 0, 0}, {1, 0, 0, 0}, {2, 0, 0, 0}, {1.5, 0, 0, 0}}});
  EXPECT_EQ(error_of(b), "glove.sim.finger[1].keyframes[3]: time goes backwards (1.5 s after 2 s)");
  b.fingers[1] = FingerScript{0, 5, {{0, 0, 0, 0}}};
  EXPECT_EQ(error_of(b), "glove.sim.finger[1].finger: 5 is not 0..4");
  b.fingers[1] = FingerScript{2, 0, {{0, 0, 0, 0}}};
  EXPECT_EQ(error_of(b), "glove.sim.finger[1].hand: 2 is not 0..1");
  b.fingers[1] = FingerScript{0, 1, {{0, 0, 0, 0}}};
  EXPECT_NE(error_of(b).find("glove.sim.finger[1]: hand 0 finger 1 is already scripted by finger[0]"),
            std::string::npos);
  b.fingers[1] = FingerScript{0, 2, {}};
  EXPECT_EQ(error_of(b), "glove.sim.finger[1].keyframes: no keyframes");

  SimConfig endless = one_finger(80, {{0, 0, 0, 0}, {1, 0, 0, 0}});
  endless.repeat = true;
  endless.dropout_probability = 1.0;
  EXPECT_NE(error_of(endless).find("glove.sim.dropout_probability"), std::string::npos);
}

// A time past int64 microseconds (or NaN) would end the script at once or never: every time is
// bounded, a script to a year and a latency to an hour, and the message prints it with %g.
TEST(SimScript, RejectsTimesBeyondAYearOrAnHour) {
  SimConfig c = one_finger(80, {{0, 0, 0, 0}, {1e13, 0, 0, 0}});
  EXPECT_EQ(error_of(c), "glove.sim.finger[0].keyframes[1]: time 1e+13 s is outside [0, 3.1536e+07] (a year)");
  c = one_finger(80, {{std::nan(""), 0, 0, 0}});
  EXPECT_EQ(error_of(c), "glove.sim.finger[0].keyframes[0]: time nan s is outside [0, 3.1536e+07] (a year)");
  c = one_finger(80, {{0, 0, 0, 0}});
  c.duration_s = 1e308;
  EXPECT_EQ(error_of(c), "glove.sim.duration_s: 1e+308 s is outside [0, 3.1536e+07] (a year)");
  c.duration_s = 365.0 * 86400.0;
  EXPECT_EQ(error_of(c), "(no error)");
  c.latency_ms = 1e13;
  EXPECT_EQ(error_of(c), "glove.sim.latency_ms: 1e+13 ms is outside [0, 3.6e+06] (an hour)");
  c.latency_ms = std::nan("");
  EXPECT_NE(error_of(c).find("glove.sim.latency_ms: nan ms"), std::string::npos);
}

TEST(SimScript, InterpolatesLinearlyAndHoldsTheEnds) {
  // From (0,0,0) at 0.5 s to (1,2,3) at 1.5 s; sampled at 10 Hz for 2 s.
  SimConfig c = one_finger(10, {{0.5, 0, 0, 0}, {1.5, 1, 2, 3}});
  c.duration_s = 2.0;
  SimScript s(c);
  const auto samples = all(s);
  ASSERT_EQ(samples.size(), 21u);  // t = 0.0, 0.1, ..., 2.0
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double t = 0.1 * static_cast<double>(k);
    const double w = std::clamp(t - 0.5, 0.0, 1.0);
    const Point3f& tip = samples[k].joints[kTipJoint[1]];
    EXPECT_NEAR(tip[0], w * 1, 1e-6) << "t=" << t;
    EXPECT_NEAR(tip[1], w * 2, 1e-6) << "t=" << t;
    EXPECT_NEAR(tip[2], w * 3, 1e-6) << "t=" << t;
    EXPECT_EQ(samples[k].device_time_us, 100'000u * k);
    EXPECT_EQ(samples[k].sequence, k);
    EXPECT_EQ(samples[k].kind, SampleKind::kPositions);
    EXPECT_EQ(samples[k].receive_time_ns, 0);
  }
}

TEST(SimScript, EndsAtTheLastKeyframeWithoutDuration) {
  SimConfig c = one_finger(100, {{0, 0, 0, 0}, {0.5, 0, 0, 1}});
  SimScript s(c);
  EXPECT_DOUBLE_EQ(s.end_time_s(), 0.5);
  EXPECT_EQ(all(s).size(), 51u);
  GloveSample g;
  EXPECT_FALSE(s.next(g));  // stays over
}

TEST(SimScript, PlacesTheOtherJointsBehindTheTipAndParksUnscriptedFingers) {
  SimConfig c = one_finger(10, {{0, 0.1, 0.2, 0.3}});
  c.fingers.push_back(FingerScript{0, 0, {{0, -0.1, 0.0, 0.5}}});
  SimScript s(c);
  GloveSample g;
  ASSERT_TRUE(s.next(g));
  // Index finger: MCP 3, PIP 4, DIP 5, tip 6.
  const float expect_z[4] = {0.3f - 0.06f, 0.3f - 0.04f, 0.3f - 0.02f, 0.3f};
  for (std::size_t j = 3; j <= 6; ++j) {
    EXPECT_FLOAT_EQ(g.joints[j][0], 0.1f);
    EXPECT_FLOAT_EQ(g.joints[j][1], 0.2f);
    EXPECT_FLOAT_EQ(g.joints[j][2], expect_z[j - 3]);
  }
  // Thumb: MCP 0, IP 1, tip 2.
  EXPECT_FLOAT_EQ(g.joints[0][2], 0.5f - 0.04f);
  EXPECT_FLOAT_EQ(g.joints[1][2], 0.5f - 0.02f);
  EXPECT_FLOAT_EQ(g.joints[2][2], 0.5f);
  // Middle, ring, little: at rest, 100 units up, offset along x.
  for (std::size_t f = 2; f < kFingers; ++f) {
    const Point3f& tip = g.joints[kTipJoint[f]];
    EXPECT_FLOAT_EQ(tip[0], 0.02f * static_cast<float>(f));
    EXPECT_FLOAT_EQ(tip[2], 100.0f);
    EXPECT_FLOAT_EQ(g.joints[kTipJoint[f] - 3][2], 100.0f - 0.06f);
  }
}

TEST(SimScript, BothHandsInterleaveInDeviceTimeOrder) {
  SimConfig c = one_finger(50, {{0, 0, 0, 0}, {0.1, 0, 0, 0}}, 1, 2);
  c.fingers.push_back(FingerScript{0, 1, {{0, 1, 1, 1}}});
  SimScript s(c);
  const auto samples = all(s);
  ASSERT_EQ(samples.size(), 12u);  // 6 ticks (0..0.1 s at 50 Hz) x 2 hands
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(samples[i].hand, i % 2);
    EXPECT_EQ(samples[i].sequence, i / 2);
    EXPECT_EQ(samples[i].device_time_us, 20'000u * (i / 2));
  }
}

TEST(SimScript, RepeatLoopsWithTheScriptsPeriod) {
  SimConfig c = one_finger(8, {{0, 0, 0, 0}, {1, 1, 0, 0}});
  c.repeat = true;
  SimScript s(c);
  EXPECT_TRUE(std::isinf(s.end_time_s()));
  const auto samples = all(s, 40);
  ASSERT_EQ(samples.size(), 40u);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const double phase = std::fmod(static_cast<double>(k) / 8.0, 1.0);
    EXPECT_NEAR(samples[k].joints[kTipJoint[1]][0], phase, 1e-6) << k;
  }
}

TEST(SimScript, JitterIsGaussianWithTheConfiguredDeviationAndSeeded) {
  SimConfig c = one_finger(1000, {{0, 0.5, 0.5, 0.5}});
  c.duration_s = 9.999;
  c.jitter_stddev = 0.01;
  c.seed = 42;
  SimScript s(c);
  const auto samples = all(s);
  ASSERT_EQ(samples.size(), 10000u);
  double sum = 0, sum2 = 0;
  for (const auto& g : samples)
    for (const float v : g.joints[kTipJoint[1]]) {
      sum += v - 0.5;
      sum2 += (v - 0.5) * (v - 0.5);
    }
  const double n = 3.0 * samples.size();
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.01, 0.01 * 0.05);

  SimScript same(c);
  const auto again = all(same);
  ASSERT_EQ(again.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) EXPECT_EQ(again[i].joints, samples[i].joints);
  s.reset();
  GloveSample first;
  ASSERT_TRUE(s.next(first));
  EXPECT_EQ(first.joints, samples[0].joints);

  c.seed = 43;
  SimScript other(c);
  GloveSample g;
  ASSERT_TRUE(other.next(g));
  EXPECT_NE(g.joints[kTipJoint[1]], samples[0].joints[kTipJoint[1]]);
}

TEST(SimScript, DropoutsShowAsSequenceGaps) {
  SimConfig c = one_finger(1000, {{0, 0, 0, 0}});
  c.duration_s = 9.999;
  c.dropout_probability = 0.3;
  c.seed = 7;
  SimScript s(c);
  const auto samples = all(s);
  EXPECT_EQ(s.generated(), 10000u);
  EXPECT_EQ(s.generated() - s.dropped(), samples.size());
  // Binomial(10000, 0.7): standard deviation about 46.
  EXPECT_NEAR(static_cast<double>(samples.size()), 7000.0, 4 * 46.0);
  std::uint64_t gaps = samples.front().sequence;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    ASSERT_GT(samples[i].sequence, samples[i - 1].sequence);
    gaps += samples[i].sequence - samples[i - 1].sequence - 1;
    // The device clock follows the sequence: both count ticks.
    EXPECT_EQ(samples[i].device_time_us, 1000u * samples[i].sequence);
  }
  gaps += 9999 - samples.back().sequence;
  EXPECT_EQ(gaps, s.dropped());
}

TEST(SimScript, ScriptedTipIsTheNoiseFreePath) {
  SimConfig c = one_finger(10, {{0, 0, 0, 0}, {2, 2, 4, 6}}, 1, 3);
  SimScript s(c);
  Point3f p;
  ASSERT_TRUE(s.scripted_tip(1, 3, 0.5, p));
  EXPECT_FLOAT_EQ(p[0], 0.5f);
  EXPECT_FLOAT_EQ(p[1], 1.0f);
  EXPECT_FLOAT_EQ(p[2], 1.5f);
  EXPECT_FALSE(s.scripted_tip(0, 3, 0.5, p));
  EXPECT_TRUE(s.hand_active(1));
  EXPECT_FALSE(s.hand_active(0));
}

}  // namespace
}  // namespace sculpt::hal
