// HandModel forward kinematics against closed forms and an independently built rotation
// matrix (Rodrigues' formula from axis and angle, not from the quaternion).

#include "sculpt/hal/hand_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace sculpt::hal {
namespace {

using Vec = std::array<double, 3>;
constexpr double kTol = 1e-5;
constexpr double kHalfPi = std::numbers::pi / 2;

Vec vec(const Point3f& p) { return {p[0], p[1], p[2]}; }
double dist(const Vec& a, const Vec& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}
void expect_near(const Point3f& got, const Vec& want, const char* what) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], kTol) << what << " axis " << i;
}

// The chain's reported joints: thumb MCP, IP, tip (chain points 1..3); fingers 0..3.
std::array<std::size_t, 4> chain_joints(std::size_t f) {
  if (f == 0) return {99, 0, 1, 2};
  const std::size_t first = kTipJoint[f - 1] + 1;
  return {first, first + 1, first + 2, first + 3};
}

TEST(HandModel, ZeroAnglesGiveStraightFingersAlongTheirRestDirection) {
  const HandModel model;
  const auto joints = model.joints_from_angles({}, WristPose{});
  for (std::size_t f = 0; f < kFingers; ++f) {
    const FingerBones& b = model.bones()[f];
    const Vec u = {std::cos(b.rest_yaw), std::sin(b.rest_yaw), 0};
    const double total = b.proximal + b.middle + b.distal;
    const Vec tip = {b.base[0] + total * u[0], b.base[1] + total * u[1], b.base[2]};
    expect_near(joints[kTipJoint[f]], tip, "tip");
    if (f > 0) expect_near(joints[chain_joints(f)[0]], vec(b.base), "MCP at base");
  }
  // The index finger reaches about 8 cm beyond its knuckle, as an adult's does.
  const FingerBones& index = model.bones()[1];
  EXPECT_NEAR(index.proximal + index.middle + index.distal, 0.081, 0.01);
}

TEST(HandModel, NinetyDegreesAtTheFirstJointPointsTheFingerIntoThePalm) {
  const HandModel model;
  std::array<FingerAngles, kFingers> angles{};
  for (auto& a : angles) a = {0, static_cast<float>(kHalfPi), 0, 0};
  const auto joints = model.joints_from_angles(angles, WristPose{});
  for (std::size_t f = 0; f < kFingers; ++f) {
    const FingerBones& b = model.bones()[f];
    const double total = b.proximal + b.middle + b.distal;
    expect_near(joints[kTipJoint[f]], {b.base[0], b.base[1], b.base[2] - total}, "tip");
  }
}

TEST(HandModel, NinetyNinetyZeroFoldsTheFingerBack) {
  const HandModel model;
  std::array<FingerAngles, kFingers> angles{};
  angles[2] = {0, static_cast<float>(kHalfPi), static_cast<float>(kHalfPi), 0};  // middle finger
  const auto joints = model.joints_from_angles(angles, WristPose{});
  const FingerBones& b = model.bones()[2];
  // Yaw 0: u = +x. Proximal points -z, the middle and distal bones point -x.
  const Vec pip = {b.base[0], b.base[1], b.base[2] - b.proximal};
  const Vec dip = {pip[0] - b.middle, pip[1], pip[2]};
  const Vec tip = {dip[0] - b.distal, dip[1], dip[2]};
  expect_near(joints[8], pip, "PIP");
  expect_near(joints[9], dip, "DIP");
  expect_near(joints[10], tip, "tip");

  // 0 / 90 / 90 with 30 degrees of abduction on the index finger.
  angles = {};
  const double a = std::numbers::pi / 6;
  angles[1] = {static_cast<float>(a), 0, static_cast<float>(kHalfPi), static_cast<float>(kHalfPi)};
  const auto j2 = model.joints_from_angles(angles, WristPose{});
  const FingerBones& i = model.bones()[1];
  const Vec u = {std::cos(i.rest_yaw + a), std::sin(i.rest_yaw + a), 0};
  const Vec pip2 = {i.base[0] + i.proximal * u[0], i.base[1] + i.proximal * u[1], i.base[2]};
  const Vec dip2 = {pip2[0], pip2[1], pip2[2] - i.middle};
  const Vec tip2 = {dip2[0] - i.distal * u[0], dip2[1] - i.distal * u[1], dip2[2]};
  expect_near(j2[4], pip2, "index PIP");
  expect_near(j2[5], dip2, "index DIP");
  expect_near(j2[6], tip2, "index tip");
}

TEST(HandModel, RandomAnglesPreserveBoneLengths) {
  const HandModel model;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<float> angle(-1.6f, 1.6f);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<FingerAngles, kFingers> angles;
    for (auto& a : angles)
      for (float& v : a) v = angle(rng);
    WristPose wrist;
    wrist.position = {angle(rng), angle(rng), angle(rng)};
    wrist.orientation = {angle(rng), angle(rng), angle(rng), angle(rng)};  // normalised inside
    const auto joints = model.joints_from_angles(angles, wrist);
    for (std::size_t f = 1; f < kFingers; ++f) {
      const FingerBones& b = model.bones()[f];
      const auto c = chain_joints(f);
      EXPECT_NEAR(dist(vec(joints[c[0]]), vec(joints[c[1]])), b.proximal, kTol);
      EXPECT_NEAR(dist(vec(joints[c[1]]), vec(joints[c[2]])), b.middle, kTol);
      EXPECT_NEAR(dist(vec(joints[c[2]]), vec(joints[c[3]])), b.distal, kTol);
    }
    const FingerBones& t = model.bones()[0];
    EXPECT_NEAR(dist(vec(joints[0]), vec(joints[1])), t.middle, kTol);
    EXPECT_NEAR(dist(vec(joints[1]), vec(joints[2])), t.distal, kTol);
  }
}

TEST(HandModel, WristPoseRotatesEveryJointAboutTheWrist) {
  const HandModel model;
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-1, 1);
  std::array<FingerAngles, kFingers> angles;
  for (auto& a : angles)
    for (float& v : a) v = static_cast<float>(u(rng));
  const auto local = model.joints_from_angles(angles, WristPose{});
  for (int trial = 0; trial < 50; ++trial) {
    Vec axis = {u(rng), u(rng), u(rng)};
    const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& c : axis) c /= n;
    const double theta = 3 * u(rng);
    // Rodrigues: R = I cos + (1 - cos) k k^T + sin [k]x.
    const double c = std::cos(theta), s = std::sin(theta);
    const double rotation[3][3] = {{c + axis[0] * axis[0] * (1 - c), axis[0] * axis[1] * (1 - c) - axis[2] * s,
                                    axis[0] * axis[2] * (1 - c) + axis[1] * s},
                                   {axis[1] * axis[0] * (1 - c) + axis[2] * s, c + axis[1] * axis[1] * (1 - c),
                                    axis[1] * axis[2] * (1 - c) - axis[0] * s},
                                   {axis[2] * axis[0] * (1 - c) - axis[1] * s,
                                    axis[2] * axis[1] * (1 - c) + axis[0] * s, c + axis[2] * axis[2] * (1 - c)}};
    WristPose wrist;
    wrist.position = {static_cast<float>(u(rng)), static_cast<float>(u(rng)), static_cast<float>(u(rng))};
    wrist.orientation = {static_cast<float>(std::cos(theta / 2)), static_cast<float>(axis[0] * std::sin(theta / 2)),
                         static_cast<float>(axis[1] * std::sin(theta / 2)),
                         static_cast<float>(axis[2] * std::sin(theta / 2))};
    const auto moved = model.joints_from_angles(angles, wrist);
    for (std::size_t j = 0; j < kJointPoints; ++j) {
      Vec want;
      for (int r = 0; r < 3; ++r)
        want[r] = rotation[r][0] * local[j][0] + rotation[r][1] * local[j][1] + rotation[r][2] * local[j][2] +
                  wrist.position[r];
      expect_near(moved[j], want, "rotated joint");
    }
  }
}

TEST(HandModel, TipsComeFromJointsOrFromKinematics) {
  const HandModel model;
  GloveSample positions;
  for (std::size_t j = 0; j < kJointPoints; ++j) positions.joints[j] = {float(j), 2.0f * j, 3.0f * j};
  const auto tips = model.tips(positions);
  for (std::size_t f = 0; f < kFingers; ++f) EXPECT_EQ(tips[f], positions.joints[kTipJoint[f]]);

  GloveSample angles;
  angles.kind = SampleKind::kAngles;
  angles.angles[3] = {0.1f, 0.5f, 0.4f, 0.3f};
  angles.wrist.position = {0.1f, 0.2f, 0.3f};
  const auto fk = model.joints_from_angles(angles.angles, angles.wrist);
  const auto tips2 = model.tips(angles);
  for (std::size_t f = 0; f < kFingers; ++f) EXPECT_EQ(tips2[f], fk[kTipJoint[f]]);
}

TEST(HandModel, RejectsBadBonesNamingTheFinger) {
  auto bones = HandModel::default_bones();
  bones[2].middle = -0.01f;
  try {
    HandModel m(bones);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "hand_model.finger[2].middle: length -0.01 is not > 0");
  }
}

}  // namespace
}  // namespace sculpt::hal
