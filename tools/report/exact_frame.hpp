#pragma once
// The exact computation of one collision frame, the reference every row of `sculpt report` is
// measured against: MATH.md §1-6 in double on an ExactState, with a brute-force nearest-point
// search on the current positions every time (no index, no drift bound), every point moved
// (global region), the session's kernel, and normals carried by Nanson's formula.
//
// It makes the thesis's decisions the way deform::Deformer makes them (the Δd source rule, the
// clearance and finger-size patch guards, the Δr pinning, the fold split), because a reference
// that decided differently would measure the decisions, not the arithmetic. Only the
// arithmetic and the search differ: double throughout, and no approximation.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "exact_state.hpp"
#include "sculpt/deform/deformer.hpp"

namespace sculpt::tools::report {

/// What one exact step did.
struct ExactReport {
  std::size_t collisions = 0;      ///< collided probes, summed over the applied frames
  std::size_t frames = 0;          ///< frames applied (more than one when the step was split)
  double max_displacement = 0.0;   ///< largest point displacement over the step
  double min_jacobian = 1.0;       ///< smallest det(I + grad u) over the applied frames
  std::uint32_t probe_inside = 0;  ///< probes ending more than Δd across the surface
  deform::GuardCounts guards;      ///< the guards the exact computation applies, as the deformer counts them
};

class ExactFrame {
 public:
  /// `initial` fixes what the deformer also fixes at set-up: the typical patch size and the
  /// probes' range. The region of `settings` is ignored (the exact frame is global); traction
  /// is not computed (it does not move the model).
  ExactFrame(const deform::PointModel& initial, const deform::DeformSettings& settings);

  /// One step (a deform() call): collide, solve, move every point, carry the normals; split
  /// into substeps along the same forces when it would fold, as the deformer does.
  ExactReport step(ExactState& state, std::span<const deform::ProbeMotion> probes) const;

  const deform::DeformSettings& settings() const { return settings_; }

 private:
  enum class Outcome { kNothing, kApplied, kFolded, kNonFinite };
  struct Contact {
    bool pressing = false;
    deform::Vec3 source, contact, force;
  };
  struct Attempt {
    std::vector<Contact> contacts;
    deform::GuardCounts guards;
    std::size_t collisions = 0;
    double max_displacement = 0.0;
    double min_jacobian = 1.0;
  };

  Outcome attempt(ExactState& state, std::span<const deform::ProbeMotion> probes, Attempt& a) const;
  std::uint32_t nearest(const ExactState& s, const deform::Vec3& q) const;
  deform::Vec3 outside_at(const ExactState& s, std::uint32_t i) const;
  double side(const ExactState& s, std::uint32_t a, const deform::Vec3& q) const;
  deform::Vec3 outward(const ExactState& s, std::uint32_t a) const;
  deform::Vec3 clear_source(const ExactState& s, const deform::Vec3& candidate, const deform::Vec3& contact,
                            const deform::Vec3& force, std::uint32_t a, double clearance, bool& moved) const;
  void patch(const ExactState& s, const deform::Vec3& centre, const deform::Vec3& u0, bool widen,
             std::vector<deform::DisplacementCondition>& rows, deform::GuardCounts& guards) const;
  std::uint32_t inside_after(const ExactState& s, std::span<const deform::ProbeMotion> probes) const;

  deform::DeformSettings settings_;
  std::size_t min_patch_points_ = 1;
  double smoothing_ = 0.0;  // the side's smoothing length h, as deform::side_smoothing fixes it
  deform::Vec3 centre_;
  double probe_range_ = 0.0;
};

}  // namespace sculpt::tools::report
