#include "sculpt/rt/haptic_shaper.hpp"

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
  const double now = deform::norm(out), wanted = deform::norm(target);
  if (wanted <= now) {
    out = target;  // falling (or turning at no more force): at once
  } else {
    // Rising: at most max_rise_per_tick_ more magnitude than last tick, along the target.
    const double allowed = now + max_rise_per_tick_;
    out = wanted <= allowed ? target : target * (allowed / wanted);
  }
  return out;
}

}  // namespace sculpt::rt
