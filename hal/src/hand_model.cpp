#include "sculpt/hal/hand_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sculpt::hal {
namespace {

// A 3x3 rotation from a quaternion (w, x, y, z), normalised here so a slightly drifted
// quaternion from a sensor still gives a rotation, not a scaling.
struct Rotation {
  std::array<std::array<float, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

Rotation rotation_from(const std::array<float, 4>& q) noexcept {
  Rotation r;
  const double n2 = double{q[0]} * q[0] + double{q[1]} * q[1] + double{q[2]} * q[2] + double{q[3]} * q[3];
  if (!(n2 > 0.0) || !std::isfinite(n2)) return r;
  const double s = 1.0 / std::sqrt(n2);
  const double w = q[0] * s, x = q[1] * s, y = q[2] * s, z = q[3] * s;
  r.m[0] = {static_cast<float>(1 - 2 * (y * y + z * z)), static_cast<float>(2 * (x * y - w * z)),
            static_cast<float>(2 * (x * z + w * y))};
  r.m[1] = {static_cast<float>(2 * (x * y + w * z)), static_cast<float>(1 - 2 * (x * x + z * z)),
            static_cast<float>(2 * (y * z - w * x))};
  r.m[2] = {static_cast<float>(2 * (x * z - w * y)), static_cast<float>(2 * (y * z + w * x)),
            static_cast<float>(1 - 2 * (x * x + y * y))};
  return r;
}

Point3f apply(const Rotation& r, const Point3f& p, const Point3f& t) noexcept {
  Point3f out;
  for (std::size_t i = 0; i < 3; ++i) out[i] = r.m[i][0] * p[0] + r.m[i][1] * p[1] + r.m[i][2] * p[2] + t[i];
  return out;
}

void check_length(std::size_t f, const char* bone, float v) {
  if (!(v > 0.0f) || !std::isfinite(v)) {
    std::ostringstream s;
    s << "hand_model.finger[" << f << "]." << bone << ": length " << v << " is not > 0";
    throw std::invalid_argument(s.str());
  }
}

}  // namespace

std::array<FingerBones, kFingers> HandModel::default_bones() noexcept {
  // Typical adult proportions (phalanx lengths after Alexander & Viktor's hand anthropometry,
  // rounded to millimetres); bases are rough knuckle positions from the wrist's centre.
  return {{
      {{0.025f, 0.020f, -0.010f}, 0.70f, 0.046f, 0.032f, 0.027f},    // thumb: CMC, splayed out
      {{0.090f, 0.024f, 0.000f}, 0.05f, 0.040f, 0.023f, 0.018f},     // index
      {{0.093f, 0.002f, 0.000f}, 0.00f, 0.045f, 0.027f, 0.019f},     // middle
      {{0.088f, -0.018f, 0.000f}, -0.05f, 0.042f, 0.026f, 0.019f},   // ring
      {{0.080f, -0.034f, -0.003f}, -0.12f, 0.033f, 0.018f, 0.017f},  // little
  }};
}

HandModel::HandModel() : bones_(default_bones()) {}

HandModel::HandModel(const std::array<FingerBones, kFingers>& bones) : bones_(bones) {
  for (std::size_t f = 0; f < kFingers; ++f) {
    const FingerBones& b = bones[f];
    check_length(f, "proximal", b.proximal);
    check_length(f, "middle", b.middle);
    check_length(f, "distal", b.distal);
    if (!std::isfinite(b.base[0]) || !std::isfinite(b.base[1]) || !std::isfinite(b.base[2]) ||
        !std::isfinite(b.rest_yaw))
      throw std::invalid_argument("hand_model.finger[" + std::to_string(f) + "]: base or rest_yaw is not finite");
  }
}

std::array<Point3f, kJointPoints> HandModel::joints_from_angles(const std::array<FingerAngles, kFingers>& angles,
                                                                const WristPose& wrist) const noexcept {
  const Rotation r = rotation_from(wrist.orientation);
  std::array<Point3f, kJointPoints> joints{};
  for (std::size_t f = 0; f < kFingers; ++f) {
    const FingerBones& b = bones_[f];
    const FingerAngles& a = angles[f];
    const float yaw = b.rest_yaw + a[0];
    const float ux = std::cos(yaw), uy = std::sin(yaw);
    const std::array<float, 3> lengths = {b.proximal, b.middle, b.distal};
    std::array<Point3f, 4> chain;
    chain[0] = b.base;
    float phi = 0.0f;
    for (std::size_t k = 0; k < 3; ++k) {
      phi += a[k + 1];
      const float c = std::cos(phi), s = std::sin(phi);
      chain[k + 1] = {chain[k][0] + lengths[k] * c * ux, chain[k][1] + lengths[k] * c * uy,
                      chain[k][2] - lengths[k] * s};
    }
    // The thumb does not report its CMC (chain[0]); every other finger reports all four.
    const std::size_t first_reported = f == 0 ? 1 : 0;
    std::size_t j = f == 0 ? 0 : kTipJoint[f - 1] + 1;
    for (std::size_t k = first_reported; k < chain.size(); ++k, ++j) joints[j] = apply(r, chain[k], wrist.position);
  }
  return joints;
}

std::array<Point3f, kFingers> HandModel::tips(const GloveSample& sample) const noexcept {
  std::array<Point3f, kFingers> out{};
  if (sample.kind == SampleKind::kAngles) {
    const auto joints = joints_from_angles(sample.angles, sample.wrist);
    for (std::size_t f = 0; f < kFingers; ++f) out[f] = joints[kTipJoint[f]];
  } else {
    for (std::size_t f = 0; f < kFingers; ++f) out[f] = sample.joints[kTipJoint[f]];
  }
  return out;
}

}  // namespace sculpt::hal
