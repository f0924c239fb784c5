#pragma once
// The region's ball queries, answered from the candidates of a wider ball found a few frames
// before while the contact and the points stay close enough to where they were.
//
// Why: in a stroke each finger's region ball is nearly the one the frame before asked for: the
// contact moves a fraction of a spacing, and the points move by the frame's displacement. A
// fresh k-d tree query for every ball, every frame, was about 40 % of a 100k-point five-finger
// stroke frame (the tree's walk, and the drift widening it as the stroke goes deeper). A ball of
// radius r + m around c0 that held every point within it when it was found still holds every
// point that is now within r of c, as long as |c - c0| plus the farthest any point has moved
// since stays within m; the frame then tests those candidates alone, at their current positions,
// by the comparison the tree's query makes, so that the answer is the same set to the bit.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

class BallCache {
 public:
  /// How much wider than asked a region's fresh ball is found, as a share of its radius: a
  /// fifth keeps a ball for a few frames of the bench's fast stroke (half a spacing a frame on a
  /// 20-spacing ball) at 1.44 times the points of one query.
  static constexpr double kRegionMargin = 0.2;
  /// The same for the small balls that locate the probes (a few spacings): half, so that a ball
  /// lasts while the finger moves about a spacing, at 2.25 times the points.
  static constexpr double kProbeMargin = 0.5;

  BallCache() = default;
  /// Room for `capacity` candidates in all (4 bytes each), balls found `margin` (a share of
  /// their radius) wider than asked; with `ascending`, each query's points come in ascending
  /// index order, as PointIndex::within_radius gives them by default (the caller sums over
  /// them: the order is part of the result). Allocates.
  BallCache(std::size_t capacity, double margin, bool ascending);
  double margin() const noexcept { return margin_; }

  /// Every point may have moved by up to `distance` more since the last call (a kept frame's
  /// stored move). Not finite: every ball is forgotten.
  void add_move(double distance) noexcept;
  /// The model's positions changed by more than add_move() was told (a restore, or a write from
  /// outside): every ball is forgotten.
  void forget() noexcept;

  /// Writes into `out` (cleared first; within its capacity, never grown) the points of `model`
  /// within `radius` of `c` at their current positions, squared distance <= radius * radius as
  /// PointIndex::within_radius compares it, in the order set at construction: from a kept ball when one
  /// still covers this ball; else, when one of the last few frames asked for a ball near this one (a
  /// stroke), from a wider query of `index` (with `drift`, as PointIndex::within_radius) whose
  /// result is kept when it fits; else (a finger that just came down, or one moving too fast
  /// for a ball to last) from a plain query, so that a single press pays nothing for the
  /// balls. Returns false when a point did not fit in `out` (or the index cannot answer for
  /// the model), as the index does. noexcept, allocation-free.
  bool within_radius(const PointModel& model, const PointIndex& index, double drift, const Vec3& c, double radius,
                     std::vector<std::uint32_t>& out) noexcept;
  /// The nearest point of `model` to q at its current position, as PointIndex::nearest finds
  /// it (ties to the smallest index), from a kept ball when one covers the ball around q
  /// through the `hint`'s current position (the nearest point lies within it); otherwise from
  /// the index. Makes no ball of its own: a probe's within_radius() that follows does.
  /// noexcept, allocation-free.
  PointIndex::Nearest nearest(const PointModel& model, const PointIndex& index, double drift, const Vec3& q,
                              std::uint32_t hint) noexcept;
  /// The frame's queries are over: a ball none of them used since the last call may be dropped
  /// when room is needed.
  void end_frame() noexcept;

  /// Since construction: queries answered from a kept ball, wider queries (their ball kept when
  /// it fits), and plain queries.
  std::size_t hits() const noexcept { return hits_; }
  std::size_t wider() const noexcept { return wider_; }
  std::size_t plain() const noexcept { return plain_; }

 private:
  // A frame of ten fingers uses up to three balls each in the probes' cache (the side's ball
  // before and after the move, the bc patch).
  static constexpr std::size_t kMaxBalls = 32;
  struct Ball {
    Vec3 centre;
    double radius = 0.0;    // every point within it of centre when it was found is a candidate
    double moved = 0.0;     // no point moved farther since
    std::size_t begin = 0;  // its candidates: pool_[begin, begin + count)
    std::size_t count = 0;
    bool used = false;  // asked for since the last end_frame()
  };
  const Ball* covering(const Vec3& c, double radius) const noexcept;
  // Whether one of the last kRecentFrames frames (not this one) asked for a ball whose centre
  // lies within `reach` of c.
  bool asked_before_near(const Vec3& c, double reach) const noexcept;
  // Makes room for `count` candidates at the pool's end, dropping the balls not used this
  // frame and moving the others to the front; false when there is no such room even then.
  bool make_room(std::size_t count) noexcept;

  std::vector<std::uint32_t> pool_;  // every kept ball's candidates, one after another
  std::array<Ball, kMaxBalls> balls_{};
  std::size_t ball_count_ = 0;
  double margin_ = kRegionMargin;
  bool ascending_ = false;
  // The centres the latest queries asked for, each with its frame, the oldest overwritten.
  // A few frames, not one: a finger that presses every other frame (guarded in between, as
  // the dragon's glide has some) is still in a stroke.
  static constexpr std::uint64_t kRecentFrames = 4;
  struct Asked {
    Vec3 centre;
    std::uint64_t frame = 0;
  };
  std::array<Asked, kRecentFrames * kMaxBalls> asked_{};
  std::size_t asked_count_ = 0, asked_next_ = 0;
  std::uint64_t frame_ = 0;  // end_frame() calls
  std::size_t hits_ = 0, wider_ = 0, plain_ = 0;
};

}  // namespace sculpt::deform
