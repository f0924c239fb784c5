#pragma once
// Rebuilds the deformer's k-d tree on a worker thread while the loop keeps deforming.

#include <atomic>
#include <cstdint>
#include <thread>

#include "sculpt/deform/deformer.hpp"

namespace sculpt::rt {

/// The loop asks for a rebuild by copying the positions into a buffer reserved at construction
/// (request), the worker builds the tree from that copy, and the loop swaps it in (install);
/// the worker then frees the old tree. The loop side is noexcept and allocation-free; queries
/// stay exact throughout because the deformer widens them by the drift since each snapshot.
class IndexRebuilder {
 public:
  explicit IndexRebuilder(std::size_t points);
  ~IndexRebuilder();
  IndexRebuilder(const IndexRebuilder&) = delete;
  IndexRebuilder& operator=(const IndexRebuilder&) = delete;

  /// Loop: snapshots `model` (taken at the deformer's current drift) for the worker. False when
  /// a rebuild is already under way.
  bool request(const deform::PointModel& model, double drift) noexcept;
  /// Loop: when a rebuilt index is ready, installs it and returns true.
  bool install(deform::Deformer& deformer) noexcept;
  std::uint64_t installed() const noexcept { return installed_; }

 private:
  enum State : int { kIdle, kRequested, kReady, kRetire, kQuit };
  void work();

  deform::PointModel snapshot_;
  deform::PointIndex fresh_;
  double drift_at_snapshot_ = 0.0;
  std::uint64_t installed_ = 0;
  std::atomic<int> state_{kIdle};
  std::thread worker_;
};

}  // namespace sculpt::rt
