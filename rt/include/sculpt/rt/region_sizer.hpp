#pragma once
// The auto region's radius, sized frame by frame to the share of the tick's budget the
// deformation may use, from the frames' measured times.
//
// A frame costs a fixed part (collision, set-up, the weight solve) and a part per point and
// force (the displacement pass). The sizer charges the whole time to the points, which on a
// growing region is the safe error: if the last frame cost a + b x for x = points * forces
// (a >= 0) and the next is aimed at the share S by scaling x by k = S / (a + b x) > 1, it costs
// a + k b x = S - a (k - 1), at most S. Growing is what overran before: the station let the radius double
// each frame (four times the points) and sized from an average that a few fast frames had
// lowered (the two-million-point station: up to 7,600 points and 1.2 ms ticks). So the region
// now grows by at most kMaxGrowth in points a frame, sized from the dearer of the average and
// the last frame, and shrinks at once.

#include <cstddef>

namespace sculpt::rt {

class RegionSizer {
 public:
  /// A region grows by at most this factor in points from one frame to the next.
  static constexpr double kMaxGrowth = 1.25;
  /// And shrinks by at most this factor (a frame far over its share comes back within two).
  static constexpr double kMaxShrink = 0.25;

  /// The deformation may use `budget_fraction` of the budget next_radius() is given, in (0, 1].
  explicit RegionSizer(double budget_fraction) noexcept : budget_fraction_(budget_fraction) {}

  /// A frame with `forces` forces (its collisions) over `region_points` points took
  /// `deform_ns`. Frames that moved nothing, and non-finite or negative times, are ignored.
  void observe(std::size_t region_points, std::size_t forces, double deform_ns) noexcept;
  /// Whether a frame has been observed (before it, next_radius() keeps the radius).
  bool ready() const noexcept { return average_ns_ > 0.0 || last_ns_ > 0.0; }
  /// The radius for the next frame, from `radius`, whose last region held `region_points`:
  /// the region's points are taken to grow with the radius squared (a ball on a surface), and
  /// each point and force to cost the dearer of per_point_force_ns() and the last frame's,
  /// aimed at the allowed share of `budget_ns`, within kMaxShrink..kMaxGrowth of the last in
  /// points.
  double next_radius(double radius, std::size_t region_points, std::size_t forces, double budget_ns) const noexcept;

  /// The frames' time per point and force, exponentially averaged (nanoseconds).
  double per_point_force_ns() const noexcept { return average_ns_; }

 private:
  double budget_fraction_;
  double average_ns_ = 0.0;  // per point and force
  double last_ns_ = 0.0;     // the last frame's, per point and force
};

}  // namespace sculpt::rt
