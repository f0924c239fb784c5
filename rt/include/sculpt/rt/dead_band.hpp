#pragma once
// The thesis's Δs discretisation (MATH.md §4): a fingertip counts as moved only when it is
// more than Δs from its last accepted position. The deformation takes its force source from
// the accepted positions before the current one, so the last three are kept.

#include <array>
#include <cstddef>

namespace sculpt::rt {

/// One fingertip's dead band. offer() is noexcept and allocation-free.
class DeadBand {
 public:
  /// @param delta_s the dead band Δs in model units (finite, >= 0; 0 accepts any change).
  /// @throw std::invalid_argument when delta_s is negative or not finite.
  explicit DeadBand(double delta_s);

  /// Offers the fingertip's newest position. Returns true when it is accepted: the first
  /// position after construction or reset(), or one strictly farther than Δs (Euclidean) from
  /// the last accepted position. A position of exactly Δs is not a move. A position with a
  /// non-finite coordinate is refused and changes nothing.
  bool offer(const std::array<double, 3>& position) noexcept;

  /// Forgets every accepted position (e.g. when the glove went stale): the next offer is accepted.
  void reset() noexcept;

  /// How many accepted positions are held: 0 to 3.
  std::size_t history_size() const noexcept { return size_; }
  /// The last accepted position. Only meaningful when history_size() >= 1.
  const std::array<double, 3>& current() const noexcept { return history_[0]; }
  /// The accepted position before current(). Only meaningful when history_size() >= 2.
  const std::array<double, 3>& previous() const noexcept { return history_[1]; }
  /// The accepted position before previous(). Only meaningful when history_size() == 3.
  const std::array<double, 3>& earlier() const noexcept { return history_[2]; }
  /// Number of positions accepted since construction or reset().
  std::size_t accepted_count() const noexcept { return accepted_; }
  double delta_s() const noexcept { return delta_s_; }

 private:
  double delta_s_;
  double delta_s_squared_;
  std::array<std::array<double, 3>, 3> history_{};  // [0] current, [1] previous, [2] earlier
  std::size_t size_ = 0;
  std::size_t accepted_ = 0;
};

}  // namespace sculpt::rt
