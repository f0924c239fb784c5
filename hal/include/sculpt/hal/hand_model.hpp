#pragma once
// Turns a glove sample into fingertips: joint positions directly, joint angles by forward
// kinematics over a hand's bone lengths.

#include <array>

#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// One finger's skeleton: where its chain starts in the hand frame and its three bones.
/// For the thumb the chain starts at the CMC joint (its metacarpal's base) and the bones are
/// the metacarpal, proximal and distal phalanges; for the other fingers the metacarpals are
/// rigid in the palm, so the chain starts at the MCP (knuckle) and the bones are the
/// proximal, middle and distal phalanges. Metres.
struct FingerBones {
  Point3f base{};         ///< the chain's first joint, from the wrist, hand frame
  float rest_yaw = 0.0f;  ///< direction at zero abduction: radians about +z from +x
  float proximal = 0.0f;  ///< first bone (thumb: metacarpal)
  float middle = 0.0f;    ///< second bone (thumb: proximal phalanx)
  float distal = 0.0f;    ///< third bone, ending at the tip
};

/// Forward kinematics of a hand.
///
/// Hand frame (right hand, the glove's convention): origin at the wrist, +x along the middle
/// finger, +y towards the thumb, +z out of the back of the hand, so the palm faces -z.
/// A finger's direction at zero angles is u = (cos yaw, sin yaw, 0) with yaw = rest_yaw +
/// abduction (abduction turns the finger about the palm normal +z, at its base). Flexion
/// turns about the finger's lateral axis and accumulates along the chain: a bone whose summed
/// flexion is phi points along cos(phi) u - sin(phi) z, so positive flexion curls towards the
/// palm. Finally the wrist pose maps the hand frame into the glove frame:
/// p_glove = R(orientation) p_hand + position.
///
/// Joint points follow glove_sample.hpp: the thumb reports its MCP, IP and tip (the chain's
/// second, third and fourth points; the CMC is not reported), the other fingers their MCP,
/// PIP, DIP and tip (all four).
class HandModel {
 public:
  /// An adult hand (index finger about 8 cm, palm about 9 cm).
  HandModel();
  /// @throw std::invalid_argument naming the finger and bone ("hand_model.finger[2].middle:
  ///   length -0.01 is not > 0") when a length is not positive and finite or a base is not
  ///   finite.
  explicit HandModel(const std::array<FingerBones, kFingers>& bones);

  /// The adult hand of the default constructor.
  static std::array<FingerBones, kFingers> default_bones() noexcept;

  const std::array<FingerBones, kFingers>& bones() const noexcept { return bones_; }

  /// Every joint point in the glove frame. A wrist quaternion that is not unit is normalised;
  /// a zero one is taken as the identity. noexcept, allocation-free.
  std::array<Point3f, kJointPoints> joints_from_angles(const std::array<FingerAngles, kFingers>& angles,
                                                       const WristPose& wrist) const noexcept;

  /// The five fingertips of a sample, glove frame: the tip joints of a positions sample, or
  /// forward kinematics of an angles sample.
  std::array<Point3f, kFingers> tips(const GloveSample& sample) const noexcept;

 private:
  std::array<FingerBones, kFingers> bones_;
};

}  // namespace sculpt::hal
