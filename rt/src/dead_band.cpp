#include "sculpt/rt/dead_band.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::rt {

DeadBand::DeadBand(double delta_s) : delta_s_(delta_s), delta_s_squared_(delta_s * delta_s) {
  if (!std::isfinite(delta_s) || delta_s < 0.0) {
    throw std::invalid_argument("dead band: delta_s must be finite and >= 0, got " + base::number_text(delta_s));
  }
}

bool DeadBand::offer(const std::array<double, 3>& position) noexcept {
  for (double c : position) {
    if (!std::isfinite(c)) return false;
  }
  if (size_ > 0) {
    const double dx = position[0] - history_[0][0];
    const double dy = position[1] - history_[0][1];
    const double dz = position[2] - history_[0][2];
    // Squared lengths compared, no sqrt: for a move of exactly Δs both sides round the same way
    // when the coordinates are exact, so the boundary is not a move, as specified.
    if (!(dx * dx + dy * dy + dz * dz > delta_s_squared_)) return false;
  }
  history_[2] = history_[1];
  history_[1] = history_[0];
  history_[0] = position;
  if (size_ < history_.size()) ++size_;
  ++accepted_;
  return true;
}

void DeadBand::reset() noexcept {
  history_ = {};
  size_ = 0;
  accepted_ = 0;
}

}  // namespace sculpt::rt
