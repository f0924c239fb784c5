#include "view_state.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sculpt::view {

render::Rgb finger_color(int finger) {
  // Five hues a fifth of the circle apart, saturated enough to read on the light clay.
  const double hue = std::fmod(0.95 + 0.2 * finger, 1.0) * 6.0;
  const double f = hue - std::floor(hue);
  const double on = 0.9, off = 0.15, up = off + (on - off) * f, down = on - (on - off) * f;
  switch (static_cast<int>(hue)) {
    case 0: return {on, up, off};
    case 1: return {down, on, off};
    case 2: return {off, on, up};
    case 3: return {off, down, on};
    case 4: return {up, off, on};
    default: return {on, off, down};
  }
}

void ViewState::tick(const TickSeen& tick) {
  last_tick_ = tick;
  ++ticks_;
  max_tick_us_ = std::max(max_tick_us_, tick.tick_time_us);
}

render::Overlay ViewState::overlay(double arrow_scale) const {
  render::Overlay overlay;
  for (const auto& [id, tip] : tips_) {
    const render::Rgb c = finger_color(tip.finger);
    // A fingertip off the surface is pale; pressed in, it takes its full colour and grows.
    const render::Rgb pale{0.5 + 0.5 * c.r, 0.5 + 0.5 * c.g, 0.5 + 0.5 * c.b};
    overlay.markers.push_back({tip.position, tip.in_contact ? c : pale, tip.in_contact ? 12.0 : 9.0});
  }
  for (const logging::CollisionRecord& e : last_frame_) {
    const render::Vec3 contact{e.contact[0], e.contact[1], e.contact[2]};
    const render::Vec3 force{e.force[0], e.force[1], e.force[2]};
    const render::Rgb c = finger_color(e.finger);
    overlay.arrows.push_back({contact, contact + arrow_scale * force, c});
    overlay.markers.push_back({contact, {0.1, 0.1, 0.1}, 5.0});
  }
  return overlay;
}

std::string ViewState::tick_text() const {
  if (ticks_ == 0) return {};
  char line[160];
  std::snprintf(line, sizeof line, "tick %lld  %.0f us (max %.0f)  budget %.0f us  overruns %lld  collisions %d",
                static_cast<long long>(last_tick_.tick), last_tick_.tick_time_us, max_tick_us_, last_tick_.budget_us,
                static_cast<long long>(last_tick_.overruns), last_tick_.collisions);
  return line;
}

}  // namespace sculpt::view
