#include "playback.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace sculpt::view {
namespace {

constexpr double kMinSpeed = 1.0 / 64.0;
constexpr double kMaxSpeed = 64.0;

}  // namespace

Playback::Playback(std::vector<double> frame_times_s, bool paused)
    : times_(std::move(frame_times_s)), paused_(paused) {}

bool Playback::key(Key key) {
  switch (key) {
    case Key::kPause: paused_ = !paused_; return true;
    case Key::kStep:
      if (!paused_ || ended()) return false;
      clock_s_ = std::max(clock_s_, times_[position_]);
      ++position_;
      return true;
    case Key::kFaster:
      if (speed_ >= kMaxSpeed) return false;
      speed_ *= 2.0;
      return true;
    case Key::kSlower:
      if (speed_ <= kMinSpeed) return false;
      speed_ /= 2.0;
      return true;
    case Key::kQuit:
    case Key::kOrbitLeft:
    case Key::kOrbitRight:
    case Key::kTiltUp:
    case Key::kTiltDown:
    case Key::kCloser:
    case Key::kFarther:
    case Key::kResetView: return false;  // the window's, not the playback's
  }
  return false;
}

void Playback::advance(double seconds) {
  if (paused_ || ended()) return;
  clock_s_ += seconds * speed_;
  while (position_ < times_.size() && times_[position_] <= clock_s_) ++position_;
}

std::string Playback::status() const {
  char line[96];
  std::snprintf(line, sizeof line, "frame %zu/%zu %s speed %gx", position_, times_.size(),
                paused_   ? "paused"
                : ended() ? "ended"
                          : "playing",
                speed_);
  return line;
}

}  // namespace sculpt::view
