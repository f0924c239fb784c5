#pragma once
// Rebuilds the deformer's k-d tree on a worker thread while the loop keeps deforming.

#include <atomic>
#include <cstdint>
#include <thread>

#include "sculpt/deform/deformer.hpp"

namespace sculpt::rt {

/// The loop asks for a rebuild (request), then copies the positions into a buffer reserved at
/// construction, at most `points_per_tick` points a tick (advance), so that no tick copies a
/// whole large model (437,645 points are 5 MB); the worker builds the tree from that copy, and
/// the loop swaps it in (install); the worker then frees the old tree. The loop side is
/// noexcept and allocation-free. Queries stay exact throughout: the deformer widens them by
/// the drift since the snapshot, and a snapshot taken over several ticks holds each point at
/// some moment after the request, so the drift counted from the request bounds them all.
class IndexRebuilder {
 public:
  static constexpr std::size_t kDefaultPointsPerTick = 16384;  // 192 KiB of floats, ~20 us

  explicit IndexRebuilder(std::size_t points, std::size_t points_per_tick = kDefaultPointsPerTick);
  ~IndexRebuilder();
  IndexRebuilder(const IndexRebuilder&) = delete;
  IndexRebuilder& operator=(const IndexRebuilder&) = delete;

  /// Loop: starts a snapshot of `model` at the deformer's current drift and copies its first
  /// points_per_tick points. False when a rebuild is already under way.
  bool request(const deform::PointModel& model, double drift) noexcept;
  /// Loop, every tick: copies the next points_per_tick points of a snapshot under way and hands
  /// the finished snapshot to the worker. Nothing to do (and nearly free) otherwise.
  void advance(const deform::PointModel& model) noexcept;
  /// Most points one request() or advance() copies.
  std::size_t points_per_tick() const noexcept { return points_per_tick_; }
  /// Loop: when a rebuilt index is ready, installs it and returns true.
  bool install(deform::Deformer& deformer) noexcept;
  std::uint64_t installed() const noexcept { return installed_; }

 private:
  enum State : int { kIdle, kRequested, kReady, kRetire, kQuit };
  void work();
  void copy_chunk(const deform::PointModel& model) noexcept;

  deform::PointModel snapshot_;
  deform::PointIndex fresh_;
  double drift_at_snapshot_ = 0.0;
  std::size_t points_per_tick_;
  std::size_t copied_ = 0;  // points of the snapshot under way copied so far (loop only)
  bool copying_ = false;    // a snapshot is being copied (loop only)
  std::uint64_t installed_ = 0;
  std::atomic<int> state_{kIdle};
  std::thread worker_;
};

}  // namespace sculpt::rt
