#pragma once
// A k-d tree over a snapshot of a point model's positions, answering exact queries against the
// model's current positions while the model deforms.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

class MovedOverlay;

/// Adds to `drift` how far a pass may have moved any point, when its largest displacement as
/// computed was `displacement` and no coordinate exceeded `extent` in magnitude before it, and
/// grows `extent` by as much: each new position is rounded to float (half an ulp per
/// coordinate, which the computed displacement leaves out), and the largest displacement itself
/// went through float. The deformer and the transfer keep their drift this way.
inline void add_stored_move(double displacement, double& drift, double& extent) noexcept {
  const double computed = displacement * (1.0 + 0x1p-20);
  const double step = computed + 0x1p-23 * (extent + computed);
  drift += step;
  if (std::isfinite(step)) extent += step;
}

/// The largest coordinate magnitude of the model: the first `extent` of add_stored_move().
double largest_coordinate(const PointModel& model) noexcept;

/// Spatial index over a snapshot of a PointModel's positions.
///
/// Building copies x, y, z into the index's own storage, so the model may be deformed freely
/// afterwards: the real-time loop moves points every tick and a fresh index is built off the
/// loop and moved into place. Between rebuilds, nearest() and within_radius() stay exact with
/// respect to the model's *current* positions as long as the caller passes a `drift` no smaller
/// than the largest distance any point has moved since the snapshot: the stale tree is searched
/// with the bounds widened by `drift`, and every candidate is then tested at its current
/// position, except that within_radius takes a subtree lying wholly within radius - drift of q
/// without testing its points (each is within the radius wherever it moved). A too-small
/// `drift` may miss points or report one up to the shortfall beyond the radius
/// (within_radius), or return a point that is not the nearest (nearest); reported distances
/// are always true at current positions. add_stored_move() keeps such a drift.
///
/// Thread safety: all const members (the queries) may run concurrently from any number of
/// threads on one index; they share no mutable state. rebuild() and assignment must not overlap
/// any query on the same object — build a new index elsewhere and move it in instead.
class PointIndex {
 public:
  /// Index value of Nearest when there is no point at all (empty index).
  static constexpr std::uint32_t kNoPoint = 0xFFFFFFFFu;

  /// An empty index (size() == 0).
  PointIndex();
  /// Builds the index over the model's current positions.
  explicit PointIndex(const PointModel& model);
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  /// Re-snapshots the model's positions and rebuilds the tree. Set-up time: allocates.
  /// Throws std::invalid_argument if the model has more than kNoPoint - 1 points.
  void rebuild(const PointModel& model);

  /// Number of points in the snapshot.
  std::size_t size() const;

  /// Result of nearest(): the point's index and its current distance to the query.
  struct Nearest {
    std::uint32_t index;
    double distance;
  };

  /// Whether `model` is one this index can answer for: the same point count as the snapshot.
  /// The queries below run inside the tick and cannot throw, so their callers check this at
  /// set-up (Deformer does) and a mismatch only ever yields "nothing found".
  bool indexes(const PointModel& model) const noexcept;

  /// Exact nearest point of `model` (current positions) to q, assuming no point moved more than
  /// `drift` since the snapshot. Ties in distance go to the smallest index. Returns
  /// {kNoPoint, +infinity} for an empty index, a non-finite query or a model the index does
  /// not index (see indexes()). Does not allocate or throw. Thread-safe (const).
  /// `hint`, when a point of the model, is a guess at the answer (the same probe's nearest point
  /// a moment ago, say): its current distance bounds the search from the start, so that under a
  /// dent, where the nearest points of the snapshot have moved away, the search does not first
  /// find a far one. The answer does not depend on it.
  Nearest nearest(const PointModel& model, const Vec3& q, double drift = 0.0,
                  std::uint32_t hint = kNoPoint) const noexcept;

  /// Indices of all points whose current position is within `radius` of q (inclusive:
  /// squared distance <= radius * radius), written into `out` (cleared first, ascending index
  /// order; the tree's spatial order instead when `ascending` is false, for a caller that
  /// orders the union of several queries once), assuming no point moved more than `drift`
  /// since the snapshot.
  /// Never allocates or throws: `out` is filled up to its capacity (reserve() it for the
  /// largest neighbourhood, the model size at most) and never grown. Returns true when the
  /// result is complete; false when a match did not fit in out.capacity() or the model is not
  /// one this index indexes (then `out` is empty). Thread-safe (const).
  bool within_radius(const PointModel& model, const Vec3& q, double radius, std::vector<std::uint32_t>& out,
                     double drift = 0.0, bool ascending = true) const noexcept;

  /// The min(k, size()) nearest snapshot points to q, closest first, with their squared
  /// distances (snapshot positions; a point at q itself is included). For set-up work such as
  /// normal estimation; resizes both vectors. Thread-safe (const).
  void k_nearest(const Vec3& q, std::size_t k, std::vector<std::uint32_t>& indices,
                 std::vector<double>& squared_distances) const;

  /// The moved list: with it, the index keeps the points that moved since its snapshot (up to
  /// `capacity` of them) and queries need no drift at all: the tree answers for the points
  /// still at their snapshot positions, the list for the moved ones at their current positions,
  /// so a query costs what the neighbourhood holds, not what the drift covers. While the list
  /// is complete (and the drift is above min_drift), the `drift` passed is not used; once more points moved than it
  /// holds (or note_moved said all did), queries widen by `drift` as without it, until a
  /// rebuild() or forget_moved() (an index swapped in by take_moved() stays so). Set-up:
  /// allocates (4 bytes per model point and 4 per slot).
  /// The list is consulted only when the drift passed is at least `min_drift`: below it, widening
  /// costs less than scanning the list (a frame's own moves are small; a stroke's are not).
  void track_moved(std::size_t capacity, double min_drift = 0.0);
  /// Every write to the indexed model's positions must be told here, with the points written
  /// (`all`: every point may have moved). Exactness depends on it. noexcept, allocation-free.
  /// With a min_drift above zero, unless the queries that follow will pass a drift of at least
  /// it (`next_drift`), the points are only set aside, and listed (their positions read) by
  /// prepare_queries(): until then queries widen by the drift.
  void note_moved(const PointModel& model, std::span<const std::uint32_t> points, bool all,
                  double next_drift = 0.0) noexcept;
  /// Queries with this `drift` follow: when they would consult the list, lists the points set
  /// aside first. For speed only (without it they widen by the drift, exactly). noexcept,
  /// allocation-free.
  void prepare_queries(const PointModel& model, double drift) noexcept;
  /// The model's positions equal the snapshot again (an undo to the positions it was built on).
  void forget_moved() noexcept;
  /// After this index was swapped in for `previous` (built from a snapshot taken after every
  /// point outside previous's list last moved): takes over previous's list and keeps of it only
  /// the points that differ from this snapshot. noexcept, allocation-free.
  void take_moved(PointIndex& previous, const PointModel& model) noexcept;
  /// Points listed (or set aside to be) as moved since the snapshot (0 without a list), and
  /// how many the list can hold.
  std::size_t moved_count() const noexcept;
  std::size_t moved_capacity() const noexcept;
  /// Whether a list is kept and complete, so queries do not depend on the drift.
  bool moved_complete() const noexcept;

 private:
  const MovedOverlay* usable_moved(double drift) const noexcept;
  // Lists the points note_moved() set aside, and brings the tree's counts up to them.
  void settle_moved(const PointModel& model) noexcept;
  // Brings the tree's per-subtree counts of unlisted points up to the list.
  void mark_listed() noexcept;
  // Whether those counts are up to the list (the moved list must be in use).
  bool counts_ready() const noexcept;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<MovedOverlay> moved_;
  double moved_min_drift_ = 0.0;
  // How many of the list's points the tree's counts reflect (the list's first ones).
  std::size_t unlisted_marked_ = 0;
  // A query asked for the list: note_moved keeps the counts up from then on. Set by const
  // queries, so it is read and written through std::atomic_ref (queries may run concurrently).
  mutable bool list_wanted_ = false;
};

}  // namespace sculpt::deform
