#pragma once
// What may reach an actuator on a person's hand: the surface's reaction on each finger, scaled
// by a gain, clamped to a safe force and limited in how fast it may rise, along any direction:
// a force that reverses builds up again from nothing, one that turns from its share along the
// new direction. Falling force and release are never delayed: they take effect in the tick
// they are asked for.

#include <cstddef>
#include <vector>

#include "sculpt/deform/vec3.hpp"

namespace sculpt::rt {

/// Scene [haptic] limits, in newtons and seconds (the glove's unit of length is the metre).
struct HapticLimits {
  double gain = 1.0;              ///< applied to the reaction before the clamp
  double max_force = 4.0;         ///< N, largest force magnitude ever sent (a glove actuator's range)
  double max_force_rate = 200.0;  ///< N/s, fastest rise of a finger's force along any direction
  double heartbeat_s = 0.1;       ///< longest silence towards a hand with no finger in contact

  /// Throws std::invalid_argument naming the bad limit.
  void validate() const;
};

/// One per station; sized at set-up for its fingers. step() is noexcept and allocation-free.
class HapticShaper {
 public:
  HapticShaper(const HapticLimits& limits, std::size_t fingers, double rate_hz);

  /// The force to send for finger `i` this tick, given the reaction it should feel (newtons,
  /// glove frame). Gain, then the clamp to max_force; then the last output falls at once to its
  /// share along the target (nothing when the target points away from it), and moves from there
  /// towards the target by at most max_force_rate / rate_hz. So the push along any direction
  /// rises by at most that a tick, a target in the output's direction but smaller is taken at
  /// once, and a target that turns is reached as fast as the limit allows.
  deform::Vec3 step(std::size_t i, const deform::Vec3& reaction) noexcept;
  /// Finger `i` lets go: its output is zero now, and a new contact rises from zero.
  void release(std::size_t i) noexcept { output_[i] = deform::Vec3{}; }
  const HapticLimits& limits() const { return limits_; }

 private:
  HapticLimits limits_;
  double max_rise_per_tick_;
  std::vector<deform::Vec3> output_;
};

}  // namespace sculpt::rt
