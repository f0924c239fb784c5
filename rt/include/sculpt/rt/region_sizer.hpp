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
#include <limits>

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
  /// `deform_ns`; `global`: it moved the whole model as the global frame (its cost is kept
  /// apart, see next_radius()). Frames that moved nothing, and non-finite or negative times,
  /// are ignored.
  void observe(std::size_t region_points, std::size_t forces, double deform_ns, bool global = false) noexcept;
  /// Whether a region frame has been observed (before it, next_radius() keeps the radius).
  bool ready() const noexcept { return average_ns_ > 0.0 || last_ns_ > 0.0; }
  /// The radius for the next frame, from `radius`, whose last region held `region_points`:
  /// the region's points are taken to grow with the radius squared (a ball on a surface), and
  /// each point and force to cost the dearer of per_point_force_ns() and the last frame's,
  /// aimed at the allowed share of `budget_ns`, within kMaxShrink..kMaxGrowth of the last in
  /// points.
  ///
  /// Or the whole model, `model_points` of them: infinity, which the deformer clamps to the
  /// radius whose ball holds the model and runs as the global frame. A global frame costs far
  /// less per point than a region frame (no queries, no union, no scattered reads: 2.2 against
  /// some 37 ns per point and force on the bundled sphere, 4 against 15 on two million points)
  /// and leaves no region error, so on a model small against the budget it is both the better
  /// and the cheaper frame. Once a global frame was seen, its own cost decides; before, one is
  /// tried when the share would pay for kGlobalTrial of the model at the region's cost.
  /// After a global frame that did not fit, the region goes straight to the share (no shrink
  /// limit); the radius then scales from the ball that held the model.
  double next_radius(double radius, std::size_t region_points, std::size_t forces, double budget_ns,
                     std::size_t model_points = std::numeric_limits<std::size_t>::max()) const noexcept;

  /// A global frame is tried when the share pays for this fraction of the model at the
  /// region's cost per point. Measured here, a region's costs 3.7 times a global frame's or
  /// more, so a trial costs about 4 / 3.7 of the share at most, within the tick.
  static constexpr double kGlobalTrial = 1.0 / 4.0;

  /// The frames' time per point and force, exponentially averaged (nanoseconds).
  double per_point_force_ns() const noexcept { return average_ns_; }

 private:
  double budget_fraction_;
  double average_ns_ = 0.0;  // per point and force
  double last_ns_ = 0.0;     // the last frame's, per point and force
  // The same for global frames, kept apart (0: none seen).
  double global_average_ns_ = 0.0;
  double global_last_ns_ = 0.0;
};

}  // namespace sculpt::rt
