#pragma once
// Playing a recorded session: which of its frames are due, given the keys (pause, step, speed)
// and the time that passed. Frames are due at their recorded time (CollisionRecord::time_s)
// divided by the speed, so a press plays as fast as it was made.

#include <cstddef>
#include <string>
#include <vector>

#include "image_window.hpp"

namespace sculpt::view {

class Playback {
 public:
  /// `frame_times_s`: each frame's recorded time, non-decreasing.
  Playback(std::vector<double> frame_times_s, bool paused);

  /// Acts on one key; true when the status changed (kQuit is not handled here).
  bool key(Key key);
  /// `seconds` of wall time passed: while playing, the clock runs at the speed.
  void advance(double seconds);
  /// The number of frames that should have been applied by now.
  std::size_t due() const { return position_; }
  std::size_t total() const { return times_.size(); }
  bool paused() const { return paused_; }
  bool ended() const { return position_ == times_.size(); }
  double speed() const { return speed_; }
  /// "frame 12/40 paused speed 1x".
  std::string status() const;

 private:
  std::vector<double> times_;
  std::size_t position_ = 0;
  double clock_s_ = 0.0;
  double speed_ = 1.0;
  bool paused_ = false;
};

}  // namespace sculpt::view
