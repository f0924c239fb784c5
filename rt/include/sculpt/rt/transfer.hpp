#pragma once
// Re-applying recorded collision frames to any model, without collision detection (thesis
// 4.4.1 and 4.5; ARCHITECTURE.md "The log is the edit history"): the events of a frame carry
// their sources, effective forces, region, kernel and material, so base model + event log is
// the sculpted model, whatever the density of the model they were recorded on.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/logging/records.hpp"

namespace sculpt::rt {

/// A recorded frame that cannot be applied: what() is "transfer: frame N: why".
class FrameRejected : public std::invalid_argument {
 public:
  FrameRejected(std::int64_t frame_id, const std::string& why);
  std::int64_t frame_id() const { return frame_id_; }
  /// The reason alone, without "transfer: frame N: ".
  const std::string& why() const { return why_; }

 private:
  std::int64_t frame_id_;
  std::string why_;
};

struct TransferOptions {
  /// How the per-point loop evaluates the kernel. Recorded frames do not say which precision
  /// the live deformer used; the default is the Deformer's own default, so a frame transferred
  /// onto a copy of the model it was recorded on reproduces it bit for bit.
  deform::FieldOptions field;
  /// Rebuild the k-d tree once the points have drifted this far since the last build. Queries
  /// stay exact under any drift; a stale tree only gets slower. 0 picks
  /// kDefaultRebuildFraction of the model's bounding-box diagonal.
  double rebuild_drift = 0.0;
};

/// The default rebuild threshold as a fraction of the bounding-box diagonal.
inline constexpr double kDefaultRebuildFraction = 0.01;

/// Applies recorded frames, one jointly solved frame at a time, to one model.
class FrameTransfer {
 public:
  /// Builds a k-d tree over `target` (which must outlive this object) and reserves the region
  /// buffers for the whole model. Throws std::invalid_argument for an empty model or a
  /// negative or non-finite rebuild drift.
  explicit FrameTransfer(deform::PointModel& target, const TransferOptions& options = {});

  /// Applies every event of ONE frame (all with the same frame_id): their sources and effective
  /// forces are superposed; kernel and material come from the records; the region is every
  /// point (kGlobal) or the union of balls of region_radius around each event's region_centre
  /// at the model's current positions (kRadius), as deform::Region::build forms it. Normals
  /// are carried when the model has them (and options.field.carry_normals).
  ///
  /// Everything is checked before any point moves, so a rejected frame leaves the model as it
  /// was: throws FrameRejected (naming the frame id) for more than kMaxSources events,
  /// mixed frame ids, kernels or materials, an index-set region (its points are not in the
  /// record), a non-positive radius, or a non-finite source or force; a frame whose result is
  /// not finite is undone (bit for bit) and rejected the same way. An empty frame does
  /// nothing. Allocates only when the index is rebuilt.
  void apply(std::span<const logging::CollisionRecord> frame);

  std::size_t frames_applied() const { return frames_; }
  std::size_t events_applied() const { return events_; }
  /// Largest distance any point may have moved since the index was built.
  double drift() const { return drift_; }
  std::size_t index_rebuilds() const { return rebuilds_; }
  /// Smallest det(I + grad u) over every point any frame moved: <= 0 means a transferred frame
  /// folded the target (possible on a model denser than the recording's; reported, not undone,
  /// since the log is the edit history).
  double min_jacobian() const { return min_jacobian_; }
  const deform::PointModel& model() const { return model_; }

 private:
  deform::PointModel& model_;
  TransferOptions options_;
  double rebuild_drift_ = 0.0;
  deform::PointIndex index_;
  double drift_ = 0.0;
  double extent_ = 0.0;  // no coordinate is larger in magnitude (deform::add_stored_move)
  std::size_t frames_ = 0;
  std::size_t events_ = 0;
  std::size_t rebuilds_ = 0;
  double min_jacobian_ = 1.0;
  deform::UndoJournal journal_;
  std::vector<std::uint32_t> points_;
  std::vector<std::uint32_t> scratch_;
  std::vector<std::uint8_t> member_;  // per-point flag, all zero between frames
};

struct TransferStats {
  std::size_t frames = 0;  // applied
  std::size_t events = 0;  // in the frames applied
  std::size_t rejected = 0;
  std::optional<std::int64_t> last_frame;  // the last frame applied
  bool stopped = false;                    // a rejected frame ended the transfer
};

/// What to do with a frame FrameTransfer::apply rejected (the model is as before it): true
/// passes over it and goes on, false stops the transfer there.
using RejectedFrameHandler = std::function<bool(const FrameRejected&)>;

/// Applies a log of events in order, frame by frame: consecutive events with the same frame_id
/// form one frame. The log's structure is validated before the first frame is applied, so a
/// malformed log leaves `target` untouched: throws FrameRejected naming the frame id when a
/// frame's events are not consecutive (split by another frame) or their number differs from
/// their frame_size. A frame FrameTransfer::apply rejects (a material out of range, forces
/// giving non-finite positions) goes to `on_rejected`; without one it is thrown, the frames
/// before it applied. `progress(done, total)` is called after each frame, counting frames.
TransferStats transfer(deform::PointModel& target, std::span<const logging::CollisionRecord> events,
                       const std::function<void(std::size_t done, std::size_t total)>& progress = {},
                       const TransferOptions& options = {}, const RejectedFrameHandler& on_rejected = {});

/// The records of one Deformer frame, appended to `out`: one per collided probe, in probe
/// order, sharing `frame_id`. Nothing is appended when the frame moved nothing (no collision,
/// or no finite solution), because replaying such a frame must not move anything either.
/// `settings` must be the deformer's settings with the region radius that was in force.
/// Returns the number of records appended.
std::size_t append_frame_records(const deform::FrameReport& report, const deform::DeformSettings& settings,
                                 std::int64_t frame_id, std::int64_t tick, std::vector<logging::CollisionRecord>& out);

}  // namespace sculpt::rt
