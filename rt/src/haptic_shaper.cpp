#include "sculpt/rt/haptic_shaper.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sculpt::rt {

void HapticLimits::validate() const {
  auto fail = [](const char* key, double v, const char* rule) {
    std::ostringstream m;
    m << "haptic." << key << " = " << v << ": " << rule;
    throw std::invalid_argument(m.str());
  };
  if (!(gain >= 0.0) || !std::isfinite(gain)) fail("gain", gain, "must be finite and >= 0");
  if (!(max_force > 0.0 && max_force <= 1e3)) fail("max_force", max_force, "must lie in (0, 1000] newtons");
  if (!(max_force_rate > 0.0) || !std::isfinite(max_force_rate)) {
    fail("max_force_rate", max_force_rate, "must be positive and finite (N/s)");
  }
  if (!(heartbeat_s > 0.0 && heartbeat_s <= 10.0)) fail("heartbeat_s", heartbeat_s, "must lie in (0, 10] seconds");
}

HapticShaper::HapticShaper(const HapticLimits& limits, std::size_t fingers, double rate_hz)
    : limits_(limits), output_(fingers) {
  limits_.validate();
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw std::invalid_argument("haptic shaper: rate must be positive");
  max_rise_per_tick_ = limits_.max_force_rate / rate_hz;
}

deform::Vec3 HapticShaper::step(std::size_t i, const deform::Vec3& reaction) noexcept {
  deform::Vec3 target = reaction * limits_.gain;
  const double magnitude = deform::norm(target);
  // A non-finite reaction is no force at all: nothing unbounded reaches the hand.
  if (!std::isfinite(magnitude)) target = deform::Vec3{};
  if (magnitude > limits_.max_force) target = target * (limits_.max_force / magnitude);
  deform::Vec3& out = output_[i];
  // Falling is at once: the last output shrinks to its share along the target (to nothing when
  // the target points away from it), a force in the output's own direction that only fell.
  // From there the output moves towards the target by at most max_rise_per_tick_. A limit on
  // the magnitude alone let a force turn at full magnitude in one tick: a reversal at 4 N is an
  // 8 N step on the hand. This way the push along any direction rises by at most the limit a
  // tick over what it was (or over zero), however the target turns.
  const double out_squared = deform::squared_norm(out);
  const double share = out_squared > 0.0 ? std::clamp(deform::dot(target, out) / out_squared, 0.0, 1.0) : 0.0;
  const deform::Vec3 fallen = out * share;
  const deform::Vec3 rise = target - fallen;
  const double rise_norm = deform::norm(rise);
  out = rise_norm <= max_rise_per_tick_ ? target : fallen + rise * (max_rise_per_tick_ / rise_norm);
  return out;
}

}  // namespace sculpt::rt
