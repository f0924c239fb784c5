#pragma once
// What the viewer shows besides the model: the fingertips, the last frame's contacts and
// forces, the tick statistics, and where its copy stands against the station's.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "sculpt/logging/records.hpp"
#include "sculpt/render/overlay.hpp"

namespace sculpt::view {

struct FingertipSeen {
  std::int64_t tick = 0;
  int hand = 0;
  int finger = 0;
  render::Vec3 position;  ///< registered: model frame
  bool in_contact = false;
};

struct TickSeen {
  std::int64_t tick = 0;
  int collisions = 0;
  double tick_time_us = 0.0;
  double budget_us = 0.0;
  std::int64_t overruns = 0;
};

class ViewState {
 public:
  void fingertip(const FingertipSeen& tip) { tips_[{tip.hand, tip.finger}] = tip; }
  void tick(const TickSeen& tick);
  /// The contacts and forces of the frame just applied replace the previous frame's.
  void frame(const std::vector<logging::CollisionRecord>& events) { last_frame_ = events; }

  /// Fingertips (rings; filled when in contact), contact points and force arrows from the
  /// contact toward the probe, `arrow_scale` times the force's length.
  render::Overlay overlay(double arrow_scale) const;
  /// The tick statistics as one line of text ("" before the first tick).
  std::string tick_text() const;
  bool any_tick() const { return ticks_ > 0; }

 private:
  std::map<std::pair<int, int>, FingertipSeen> tips_;
  std::vector<logging::CollisionRecord> last_frame_;
  TickSeen last_tick_;
  std::size_t ticks_ = 0;
  double max_tick_us_ = 0.0;
};

/// One colour per finger (thumb .. little).
render::Rgb finger_color(int finger);

}  // namespace sculpt::view
