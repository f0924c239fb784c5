#pragma once
// One collision frame (thesis 4.2-4.3, MATH.md §3-6): collide -> forces and boundary conditions
// -> solve -> move the region -> carry normals -> keep free fingers outside.

#include <cstddef>
#include <span>
#include <vector>

#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/kernel.hpp"
#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/region.hpp"
#include "sculpt/deform/weight_solver.hpp"

namespace sculpt::deform {

struct DeformSettings {
  Kernel kernel;
  ContactSettings contact;
  RegionSettings region;
  SolverOptions solver;
  FieldOptions field;
  /// Compute the traction at each contact and its resultant over the contact neighbourhood
  /// (for haptic feedback). Needs normals; off leaves the work out entirely.
  bool traction = false;
  std::size_t max_probes = kMaxSources;
};

/// What happened to one probe in a frame.
enum class ProbeState {
  kFree,           ///< outside, farther than Δr: no effect
  kGuarded,        ///< outside within Δr of the surface while another finger pressed: pinned its surface
  kCollided,       ///< crossed the surface: a source with force F
  kStartedInside,  ///< its previous position was already across the surface: ignored (no force)
};

struct ContactReport {
  ProbeState state = ProbeState::kFree;
  std::uint32_t nearest = PointIndex::kNoPoint;  ///< A, nearest model point to the probe
  Vec3 contact;                                   ///< A's position before the frame
  double distance = 0.0;                          ///< |P_f - A|
  Vec3 source;                                    ///< where the force acts
  SourceRule source_rule = SourceRule::kPrevious;
  Vec3 force;                                     ///< F = P_f - A
  Vec3 weights;                                   ///< alpha of MATH.md §3
  Vec3 effective_force;                           ///< f: logged, and used for traction
  std::size_t boundary_points = 0;                ///< points in the eps-neighbourhood of A
  double side_after = 0.0;                        ///< the probe's side after the frame (< 0 inside)
  bool pushed_out = false;                        ///< found across the surface after the frame and moved out
  Vec3 probe_after;                               ///< the probe position after the frame
  bool has_traction = false;
  Vec3 traction;                                  ///< t at A (force per area)
  Vec3 traction_resultant;                        ///< sum of t over the neighbourhood times area per point
};

struct FrameReport {
  std::vector<ContactReport> contacts;  ///< one per probe, in the order given
  std::size_t collisions = 0;
  SolveReport solve;
  std::size_t displacement_conditions = 0;
  std::size_t region_points = 0;  ///< points computed and moved
  std::size_t border_points = 0;
  double max_displacement = 0.0;
  double max_contact_displacement = 0.0;  ///< largest over the contact neighbourhoods
  double max_border_displacement = 0.0;   ///< largest over the pinned band
};

/// Deforms one model frame by frame. Construction may allocate and throw (clear messages for
/// bad settings); deform() allocates nothing once constructed and throws nothing.
class Deformer {
 public:
  /// Builds the k-d tree over `model` (which must outlive the deformer) and reserves every
  /// buffer a frame needs.
  Deformer(PointModel& model, const DeformSettings& settings);

  /// Runs one collision frame for up to settings.max_probes probes, solved jointly.
  const FrameReport& deform(std::span<const ProbeMotion> probes) noexcept;

  /// Largest distance any point moved since the index was built; queries stay exact.
  double drift() const { return drift_; }
  /// Rebuilds the k-d tree on the current positions (allocates: keep it off the real-time path).
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
  /// Changes the radius of a kRadius region between frames (the loop sizes it to its budget).
  /// Clamped to the smallest radius the region accepts; returns the radius in force.
  double set_region_radius(double radius) noexcept;
  /// The smallest radius a kRadius region accepts: the bc radius plus the band, and a margin.
  double min_region_radius() const noexcept;
  /// The pinned band of the last frame's region.
  std::span<const std::uint32_t> region_border() const { return region_.border(); }
  const PointModel& model() const { return model_; }
  const DeformSettings& settings() const { return settings_; }

 private:
  std::size_t add_neighbourhood(const Vec3& centre, const Vec3& displacement, bool record);
  double field_magnitude_max(std::span<const std::uint32_t> points) const;
  void compute_tractions();
  void keep_probes_outside(std::span<const ProbeMotion> probes);

  PointModel& model_;
  DeformSettings settings_;
  PointIndex index_;
  double drift_ = 0.0;
  bool index_holds_base_ = true;  // the index snapshot is the model as constructed
  double point_area_ = 0.0;
  Region region_;
  WeightSolver solver_;
  FrameReport report_;
  std::vector<SourceSetup> sources_;
  std::vector<SourceForce> forces_;
  std::vector<Vec3> weights_, effective_;
  std::vector<DisplacementCondition> conditions_;
  std::vector<Vec3> contact_points_;
  std::vector<std::uint32_t> neighbours_;
  std::vector<std::uint32_t> contact_neighbourhood_;  // every contact's bc points, contact by contact
  std::vector<std::size_t> neighbourhood_begin_;     // where each probe's points start in it
};

}  // namespace sculpt::deform
