#pragma once
// What a glove delivers, whatever the transport: one timestamped sample per hand.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sculpt/base/vec3.hpp"

namespace sculpt::hal {

inline constexpr std::size_t kHands = 2;
inline constexpr std::size_t kFingers = 5;  ///< 0 thumb, 1 index, 2 middle, 3 ring, 4 little
/// The thesis's glove tracked 19 points per hand: the thumb's MCP, IP and tip, then for each
/// other finger its MCP, PIP, DIP and tip (thumb 0-2, index 3-6, middle 7-10, ring 11-14,
/// little 15-18).
inline constexpr std::size_t kJointPoints = 19;
inline constexpr std::array<std::size_t, kFingers> kTipJoint = {2, 6, 10, 14, 18};

using Point3f = base::Float3;

enum class SampleKind : std::uint8_t {
  kPositions = 1,  ///< joints[] holds Cartesian joint positions in the glove frame
  kAngles = 2,     ///< angles[] and wrist hold joint angles, turned into tips by a HandModel
};

/// Per finger: abduction, then flexion of its three joints (MCP, PIP, DIP; for the thumb CMC,
/// MCP, IP), radians.
using FingerAngles = std::array<float, 4>;

struct WristPose {
  Point3f position{};                            ///< glove frame
  std::array<float, 4> orientation{1, 0, 0, 0};  ///< unit quaternion w, x, y, z
};

/// Trivially copyable and fixed-size, so it passes through lock-free queues by value.
struct GloveSample {
  std::uint8_t hand = 0;
  SampleKind kind = SampleKind::kPositions;
  std::uint32_t sequence = 0;        ///< the device's counter; gaps are counted, not fatal
  std::uint64_t device_time_us = 0;  ///< the device's own clock
  std::int64_t receive_time_ns = 0;  ///< host CLOCK_MONOTONIC when the sample was decoded
  std::array<Point3f, kJointPoints> joints{};
  std::array<FingerAngles, kFingers> angles{};
  WristPose wrist;
};

/// Whether every number the sample carries is finite. The binary codecs refuse a frame that is
/// not (a framing error), but a sample can also come from a simulation or a decoder that cannot
/// tell, and one inf would reach a position through the filter.
inline bool all_finite(const GloveSample& s) noexcept {
  const auto finite = [](const auto& values) {
    for (const float v : values) {
      if (!std::isfinite(v)) return false;
    }
    return true;
  };
  for (const Point3f& p : s.joints) {
    if (!finite(p)) return false;
  }
  for (const FingerAngles& a : s.angles) {
    if (!finite(a)) return false;
  }
  return finite(s.wrist.position) && finite(s.wrist.orientation);
}

}  // namespace sculpt::hal
