#pragma once
// The points that moved since a k-d tree's snapshot, kept beside the tree so that its queries
// need no widening by the drift: the tree answers exactly for the points still at their
// snapshot positions, this list for the others, at their current positions.
//
// Why: widening by the drift makes every query near a finger visit every point within the
// drift of it. On a dense scan that is thousands of points per query once a press has gone a
// few spacings deep (a two-million-point sphere: 41 % of the loop's time was such queries),
// and the rebuild that would reset the drift takes a second or more at that size.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// Squared distance from q to the point (x, y, z), in double. The one formula every exact test
/// of the index uses, so that the tree and this list agree on ties.
inline double squared_distance_to(float x, float y, float z, const double* q) noexcept {
  const double dx = static_cast<double>(x) - q[0];
  const double dy = static_cast<double>(y) - q[1];
  const double dz = static_cast<double>(z) - q[2];
  return dx * dx + dy * dy + dz * dz;
}

/// Squared distance from q to point i of the model at its current position.
inline double current_squared_distance(const PointModel& model, std::uint32_t i, const double* q) noexcept {
  return squared_distance_to(model.x[i], model.y[i], model.z[i], q);
}

class MovedOverlay {
 public:
  /// Room for `capacity` moved points of a model of `model_size` points. Allocates.
  MovedOverlay(std::size_t model_size, std::size_t capacity);

  /// `points` may have new positions now (read from the model at query time). A point beyond
  /// the capacity overflows the list: it is then incomplete until clear().
  void note(const PointModel& model, std::span<const std::uint32_t> points) noexcept;
  /// `points` may have new positions now, to be listed by settle(): until then queries must not
  /// use the list (settled() is false). Listing reads each point's position and slot, scattered
  /// through the model (a tenth of a region frame); a frame whose queries will not consult the
  /// list need not pay for it, and a point written by several such frames is listed once.
  void defer(const PointModel& model, std::span<const std::uint32_t> points) noexcept;
  /// Lists the deferred points at their current positions.
  void settle(const PointModel& model) noexcept;
  bool settled() const noexcept { return pending_count_ == 0; }
  /// Every point may have moved (a global frame): the list is incomplete until clear().
  void note_all() noexcept { overflowed_ = true; }
  /// The snapshot equals the model again: nothing has moved.
  void clear() noexcept;
  /// A new snapshot was taken (after every point outside this list last moved): keeps only the
  /// listed points for which `differs(i)` (the current position is not the snapshot's).
  template <class Differs>
  void retain(const PointModel& model, Differs differs) noexcept {
    if (overflowed_) return;  // who moved is not known: stays incomplete
    settle(model);
    std::size_t kept = 0;
    for (std::size_t s = 0; s < count_; ++s) {
      const std::uint32_t i = ids_[s];
      slot_[i] = 0;
      listed_[i / 64] &= ~(std::uint64_t{1} << (i % 64));
      if (differs(i)) ids_[kept++] = i;
    }
    count_ = 0;
    reset_boxes();
    // Listed again in the same order, each into the slot it is read from.
    note(model, std::span<const std::uint32_t>(ids_.data(), kept));
  }

  /// Whether every moved point is listed (otherwise queries must fall back on the drift).
  bool complete() const noexcept { return !overflowed_; }
  bool contains(std::uint32_t i) const noexcept { return (listed_[i / 64] >> (i % 64)) & 1u; }
  std::size_t size() const noexcept { return count_; }
  /// Deferred points not yet listed: size() + this is what the list will hold once settled.
  std::size_t pending_new() const noexcept { return pending_new_; }
  /// The listed points in the order they were listed (a point noted again keeps its place).
  std::span<const std::uint32_t> listed() const noexcept { return {ids_.data(), count_}; }
  std::size_t capacity() const noexcept { return ids_.size(); }

  /// Improves (best, best_squared) with the listed points at their current positions: a point
  /// wins when closer, or as close with a smaller index.
  void nearest(const PointModel& model, const double* q, std::uint32_t& best, double& best_squared) const noexcept;
  /// Appends the listed points within sqrt(radius_squared) of q (current positions) to `out`,
  /// within its capacity; false when one did not fit.
  bool within_radius(const PointModel& model, const double* q, double radius_squared,
                     std::vector<std::uint32_t>& out) const noexcept;

 private:
  // Slots in blocks of this many, each with a box around its points' positions since they were
  // listed (it only grows, so it covers every position a listed point has had): a query skips
  // a block whose box is farther than its bound.
  static constexpr std::size_t kBlock = 32;
  // Blocks in groups of this many, each with a box around its blocks' boxes: a query far from
  // a frame's region skips its blocks a group at a time (a stroke lists thousands of points,
  // and nearest() is asked dozens of times a frame).
  static constexpr std::size_t kGroup = 32;
  struct Box {
    float low[3], high[3];
  };
  /// Calls visit(first, last) for the slot ranges of the blocks whose box comes within
  /// sqrt(bound) of q (bound read afresh for each: a nearest search tightens it as it goes).
  template <class Visit>
  void for_each_block_near(const double* q, const double& bound, Visit visit) const noexcept {
    constexpr std::size_t kGroupSlots = kBlock * kGroup;
    for (std::size_t group = 0; group < count_; group += kGroupSlots) {
      if (box_squared_distance(groups_[group / kGroupSlots], q) > bound) continue;
      const std::size_t group_end = std::min(group + kGroupSlots, count_);
      for (std::size_t first = group; first < group_end; first += kBlock) {
        if (box_squared_distance(boxes_[first / kBlock], q) > bound) continue;
        visit(first, std::min(first + kBlock, count_));
      }
    }
  }
  /// Lists point i if it is not yet listed; its slot + 1, or 0 when the list overflowed.
  std::size_t list(std::uint32_t i) noexcept;
  void reset_boxes() noexcept;
  static double box_squared_distance(const Box& b, const double* q) noexcept;

  std::vector<std::uint32_t> slot_;          // per model point: its slot + 1, or 0 when not listed
  std::vector<std::uint64_t> listed_;        // the same as bits (what a query reads: 1/32 the memory)
  std::vector<std::uint32_t> ids_;           // the listed points, slot order
  std::vector<Box> boxes_;                   // one per block of kBlock slots
  std::vector<Box> groups_;                  // one per kGroup blocks
  std::vector<std::uint32_t> pending_;       // deferred points, each once, in the order first deferred
  std::vector<std::uint64_t> pending_bits_;  // per model point: deferred and not yet settled
  std::size_t pending_count_ = 0;
  std::size_t pending_new_ = 0;  // of them, those not listed
  std::size_t count_ = 0;
  bool overflowed_ = false;
};

}  // namespace sculpt::deform
