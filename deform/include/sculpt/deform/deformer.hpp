#pragma once
// One collision frame (thesis 4.2-4.3, MATH.md §3-6): collide -> forces and boundary conditions
// -> solve -> move the region -> carry normals -> keep free fingers outside.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sculpt/deform/ball_cache.hpp"
#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/kernel.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/region.hpp"
#include "sculpt/deform/weight_solver.hpp"

namespace sculpt::deform {

/// The stability guards of a frame (README "Stability"; MATH.md §4 and §6). Each one that acts
/// is counted in the frame's GuardCounts; none is silent.
struct GuardSettings {
  /// A source keeps at least max(Δd, clearance_ratio |F|) from every model point. On the force
  /// axis det(I + grad u) = (1 - U/h)(1 + U/(4(1 - nu)h))^2 with U = |F| at A, so a ratio of 2
  /// keeps det near 0.5 or above there; off the axis the Jacobian guard below decides.
  double clearance_ratio = 2.0;
  /// Sources also keep the finger's radius (the bc radius eps) from every model point: a
  /// fingertip ball presses like a point force at its centre.
  bool finger_radius_clearance = true;
  /// Every moved point must keep det(I + grad u) above this. A frame that does not is undone
  /// and re-run in smaller steps along the same force.
  double min_jacobian = 0.2;
  /// A folding frame is halved at most this often: at most 2^max_split_depth substeps.
  int max_split_depth = 5;
  /// The patch u0 = F covers at least this fraction of the points an eps-ball holds on the
  /// undeformed model (the finger's own size), widened when a long push has thinned it.
  double min_patch_fraction = 0.75;
  /// Probes farther than this many bounding-box diagonals from the model's centre are dropped.
  double probe_range = 1e3;

  /// Throws std::invalid_argument naming the bad setting.
  void validate() const;
};

/// How often each guard acted: per frame in FrameReport, summed by callers.
struct GuardCounts {
  std::uint32_t source_moved = 0;   ///< sources moved out to keep their clearance
  std::uint32_t fold_splits = 0;    ///< a frame that would fold was undone and halved
  std::uint32_t fold_rejected = 0;  ///< a substep still folding at the depth limit: undone, dropped
  std::uint32_t non_finite = 0;     ///< a frame with a non-finite result: undone, dropped
  std::uint32_t pushed_out = 0;     ///< fingers moved back out of the surface after a frame
  std::uint32_t damped = 0;         ///< solves that fell back to Tikhonov damping
  std::uint32_t probe_dropped = 0;  ///< probes not finite or out of range: ignored
  std::uint32_t patch_widened = 0;  ///< contact patches widened to the finger's size

  GuardCounts& operator+=(const GuardCounts& o) noexcept;
  std::uint32_t total() const noexcept;
};

/// Visits every guard count with its name (for JSON, logs and reports).
template <typename F>
void for_each_guard(const GuardCounts& g, F&& f) {
  f("source_moved", g.source_moved);
  f("fold_splits", g.fold_splits);
  f("fold_rejected", g.fold_rejected);
  f("non_finite", g.non_finite);
  f("pushed_out", g.pushed_out);
  f("damped", g.damped);
  f("probe_dropped", g.probe_dropped);
  f("patch_widened", g.patch_widened);
}

struct DeformSettings {
  Kernel kernel;
  ContactSettings contact;
  RegionSettings region;
  SolverOptions solver;
  FieldOptions field;
  /// Compute the traction at each contact and its resultant over the contact neighbourhood
  /// (for haptic feedback). Needs normals; off leaves the work out entirely.
  bool traction = false;
  /// Compute what the frame's solution gives at the contact neighbourhoods and the pinned band
  /// (FrameReport::max_contact_displacement, max_border_displacement): a diagnostic for
  /// `sculpt deform`'s JSON and the tests; no decision of the frame reads it. Off leaves the
  /// work out (the station: about 8 % of a 100k dragon's five-finger region frame, the band's
  /// 440 points evaluated against every source in double).
  bool measure_extremes = true;
  std::size_t max_probes = kMaxSources;
  GuardSettings guards;
  /// 1: the frame runs on the caller's core. 2: a worker started with the deformer shares the
  /// parts of every large displacement pass with the caller (bit for bit the same result).
  int threads = 1;
};

/// What happened to one probe in a frame.
enum class ProbeState {
  kFree,           ///< outside, farther than Δr: no effect
  kGuarded,        ///< outside within Δr of the surface while another finger pressed: pinned its surface
  kCollided,       ///< crossed the surface: a source with force F
  kStartedInside,  ///< its previous position was already across the surface: ignored (no force)
  kDropped,        ///< not finite, or out of the model's range: ignored and counted
};

struct ContactReport {
  ProbeState state = ProbeState::kFree;
  std::uint32_t nearest = PointIndex::kNoPoint;  ///< A, nearest model point to the probe
  Vec3 contact;                                  ///< A's position before the frame
  double distance = 0.0;                         ///< |P_f - A|
  Vec3 source;                                   ///< where the force acts
  SourceRule source_rule = SourceRule::kPrevious;
  Vec3 force;                       ///< F = P_f - A
  Vec3 weights;                     ///< alpha of MATH.md §3
  Vec3 effective_force;             ///< f: logged, and used for traction
  std::size_t boundary_points = 0;  ///< points in the eps-neighbourhood of A
  double side_after = 0.0;          ///< the probe's side after the frame (< 0 inside)
  /// How far the probe was still across the surface after the frame, before any push-out
  /// (0 when it ended outside): what the solve missed.
  double miss = 0.0;
  bool pushed_out = false;  ///< found across the surface after the frame and moved out
  Vec3 probe_after;         ///< the probe position after the frame
  bool has_traction = false;
  Vec3 traction;            ///< t at A (force per area)
  Vec3 traction_resultant;  ///< sum of t over the neighbourhood times area per point
};

struct FrameReport {
  std::vector<ContactReport> contacts;  ///< one per probe, in the order given
  std::size_t collisions = 0;
  SolveReport solve;
  std::size_t displacement_conditions = 0;
  /// Patches (contact or guarded finger) that held more than contact.max_patch_points and were
  /// thinned evenly to it.
  std::size_t patches_thinned = 0;
  std::size_t region_points = 0;  ///< points computed and moved
  std::size_t border_points = 0;
  /// Every point moved, as the global frame: a global region, or a radius region that held the
  /// model or would have cost more (RegionSettings::global_when_cheaper). Its log records say
  /// global, so that a transfer moves what the frame moved.
  bool global = false;
  double max_displacement = 0.0;
  /// Largest over the contact neighbourhoods and over the pinned band; 0 unless
  /// DeformSettings::measure_extremes.
  double max_contact_displacement = 0.0;
  double max_border_displacement = 0.0;
  double min_jacobian = 1.0;  ///< smallest det(I + grad u) over the moved points
  /// With FieldOptions::normal_skip_bound: the moved points that kept their normal, and the
  /// largest bound on how far (radians) a kept normal is from the carried one.
  std::size_t normals_bounded = 0;
  double max_normal_bound_angle = 0.0;
  double max_miss = 0.0;  ///< largest ContactReport::miss
  bool rejected = false;  ///< undone by a guard: the model is as before it
  GuardCounts guards;
};

/// Deforms one model frame by frame. Construction may allocate and throw (clear messages for
/// bad settings); deform() allocates nothing once constructed and throws nothing.
class Deformer {
 public:
  /// Builds the k-d tree over `model` (which must outlive the deformer) and reserves every
  /// buffer a frame needs.
  Deformer(PointModel& model, const DeformSettings& settings);

  /// Runs one collision frame for up to settings.max_probes probes, solved jointly. When the
  /// frame would fold the material it is undone and run as substeps (see frames()); the report
  /// returned is then the step as a whole: the last substep's contacts, with the traction
  /// resultants, guard counts, collisions and moved points summed over the substeps.
  const FrameReport& deform(std::span<const ProbeMotion> probes) noexcept;

  /// The frames the last deform() call applied to the model, in order: one when it ran whole,
  /// several when it was split, none when it moved nothing or was undone. Each is a frame of
  /// its own for the log, so that replay reproduces the step exactly.
  std::span<const FrameReport> frames() const { return std::span(substeps_).first(applied_); }

  /// Largest distance any point moved since the index was built; queries stay exact.
  double drift() const { return drift_; }
  /// Rebuilds the k-d tree on the current positions, however they were written, and measures
  /// the model again (allocates: keep it off the real-time path).
  void rebuild_index();
  /// Swaps in an index built elsewhere (off the real-time path) from a snapshot of the positions
  /// taken when drift() was `drift_at_snapshot`; `fresh` receives the old index, for the caller
  /// to destroy off the loop. noexcept and allocation-free.
  void adopt_index(PointIndex& fresh, double drift_at_snapshot) noexcept;
  /// Undo to `base`, the model as it was when the deformer was built: copies its positions and
  /// normals back. The drift returns to zero when the index still holds that base; otherwise
  /// the index is rebuilt. Throws std::invalid_argument when `base` has another size or layout.
  void restore(const PointModel& base);
  const PointIndex& index() const { return index_; }
  /// Queries answered from balls kept across frames (the region's and the probes'), since
  /// construction: how much a stroke used them.
  std::size_t kept_ball_hits() const noexcept { return region_.balls().hits() + probe_balls_.hits(); }
  /// Changes the radius of a kRadius region between frames (the loop sizes it to its budget).
  /// Clamped to the smallest radius the region accepts; returns the radius in force.
  double set_region_radius(double radius) noexcept;
  /// The smallest radius a kRadius region accepts: the bc radius plus the band, and a margin.
  double min_region_radius() const noexcept;
  /// The pinned band of the last frame's region.
  std::span<const std::uint32_t> region_border() const { return region_.border(); }
  const PointModel& model() const { return model_; }
  const DeformSettings& settings() const { return settings_; }
  /// The second core's worker (settings.threads == 2), else null.
  const FieldWorker* worker() const noexcept { return worker_.get(); }
  /// A probe position the deformer accepts: finite and within guards.probe_range bounding-box
  /// diagonals of the model's centre (so squared distances stay finite in float).
  bool probe_in_range(const Vec3& p) const noexcept;

 private:
  enum class Outcome { kNothing, kApplied, kFolded, kNonFinite };
  Outcome run_frame(std::span<const ProbeMotion> probes, FrameReport& r) noexcept;
  void split_frame(std::span<const ProbeMotion> probes, const FrameReport& folded) noexcept;
  void merge_step(std::size_t probe_count) noexcept;
  bool probe_usable(const ProbeMotion& motion) const noexcept;
  Vec3 outward(std::uint32_t point) const noexcept;
  Vec3 clear_source(const Vec3& candidate, const Vec3& contact, const Vec3& force, std::uint32_t nearest,
                    double clearance, bool& moved) noexcept;
  std::size_t add_neighbourhood(const Vec3& centre, const Vec3& displacement, bool record, bool widen,
                                FrameReport& r) noexcept;
  double field_magnitude_max(std::span<const std::uint32_t> points) const noexcept;
  void compute_tractions(FrameReport& r) noexcept;
  void keep_probes_outside(std::span<const ProbeMotion> probes, FrameReport& r) noexcept;
  // A and the side of a probe on the current model (contact.hpp's locate, with this deformer's
  // scratch and smoothing length); `hint` a guess at A (see PointIndex::nearest).
  SurfaceSide locate_probe(const Vec3& probe, std::uint32_t hint) noexcept;

  PointModel& model_;
  DeformSettings settings_;
  std::unique_ptr<FieldWorker> worker_;  // with settings.threads == 2
  PointIndex index_;
  double drift_ = 0.0;
  // No coordinate of the model is larger in magnitude (grown by every pass): the rounding
  // add_stored_move() adds to the drift scales with it.
  double extent_ = 0.0;
  bool index_holds_base_ = true;  // the index snapshot is the model as constructed
  double point_area_ = 0.0;
  Region region_;
  WeightSolver solver_;
  FrameReport report_;                   // the step as a whole
  std::vector<FrameReport> substeps_;    // 2^max_split_depth + 1 slots, reserved
  std::size_t applied_ = 0;              // frames of the last step kept in substeps_
  std::vector<ProbeMotion> sub_probes_;  // the motions of a substep
  UndoJournal journal_;
  FrameReport folded_;                 // what a folded first attempt decided
  const FrameReport* last_ = nullptr;  // the last attempt of the step
  GuardCounts carried_;                // guards of attempts undone on the way
  std::size_t min_patch_points_ = 1;
  Vec3 centre_;
  double probe_range_ = 0.0;  // farthest a probe may be from centre_
  std::vector<SourceSetup> sources_;
  std::vector<SourceForce> forces_;
  std::vector<Vec3> weights_, effective_;
  std::vector<DisplacementCondition> conditions_;
  std::vector<Vec3> contact_points_;
  std::vector<std::uint32_t> neighbours_;
  std::vector<std::uint32_t> side_neighbours_;  // locate()'s scratch, reserved for the whole model
  double side_smoothing_ = 0.0;                 // locate()'s h (side_smoothing)
  BallCache probe_balls_;  // the probes' small balls (locate, the bc patch, the source's clearance), kept across frames
  std::vector<std::uint32_t> contact_neighbourhood_;  // every contact's bc points, contact by contact
  std::vector<std::size_t> neighbourhood_begin_;      // where each probe's points start in it
  std::vector<double> patch_area_scale_;              // per probe: patch points before thinning / after
  double last_patch_scale_ = 1.0;                     // add_neighbourhood's thinning of its last patch
  // Per probe: A when it was last located, the nearest-point search's first guess next time (a
  // finger moves little between frames; under a dent the guess spares the search the snapshot
  // points the dent moved away).
  std::vector<std::uint32_t> probe_hints_;
};

}  // namespace sculpt::deform
