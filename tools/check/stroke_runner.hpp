#pragma once
// Drives a Deformer the way a glove does: fingers with accepted positions, one frame after
// another, each frame's output the next one's input. Every frame is judged by the independent
// surface oracle and the model itself is scanned for non-finite values; nothing here takes the
// deformer's word for where a finger is.
//
// The driver works in the case's own coordinates ("base"); the model and the probes live in a
// similarity frame of it (scaled, rotated, shifted), so the same stroke can be run in several
// frames and compared.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "invariants.hpp"
#include "mesh_side.hpp"
#include "sculpt/deform/deformer.hpp"
#include "surface_side.hpp"

namespace sculpt::tools::check {

/// The model's point spacing, the length every default offset is derived from. The one place
/// that names deform's spacing statistic.
double model_spacing(const deform::PointModel& model);

/// The sweep's axes for one case.
struct CaseSettings {
  double poisson_ratio = 0.45;
  double shear_modulus = 3e7;
  deform::KernelKind kernel = deform::KernelKind::kKelvin;
  deform::WeightForm form = deform::WeightForm::kForce;
  deform::Precision precision = deform::Precision::kFloat;
  double scale = 1.0;      ///< the model (and its probes) scaled by this
  double bc_factor = 1.0;  ///< bc radius in spacings (1, as `sculpt deform` sets it)
};

/// What the frames of one run showed. Lengths are in base units. probe_inside, passed_through
/// and deepest are the judging oracle's: the winding number of the case's mesh where that mesh
/// is closed (the sphere's hull), else the PCA plane. The pca_ and mesh_ counts are each
/// oracle's own, kept beside them so that where they disagree it shows: on an open sheet the
/// mesh's side comes from a pseudo-normal over triangles a slide stretches to 2.4 spacings, an
/// interpolation as uncertain as the plane's, so there it informs and does not judge.
struct Metrics {
  std::size_t steps = 0;           ///< deform() calls
  std::size_t frames_applied = 0;  ///< frames the deformer applied (substeps counted)
  std::size_t collisions = 0;
  std::uint32_t non_finite = 0;      ///< steps after which a coordinate or normal was not finite
  std::uint32_t probe_inside = 0;    ///< finger-steps ending more than Δd inside (oracle)
  std::uint32_t passed_through = 0;  ///< finger-steps pressing in past Δd without a collision
  double max_condition = 0.0;        ///< over applied frames; the kept-rank condition when rank-deficient
  double max_relative_residual = 0.0;
  double max_displacement_ratio = 0.0;  ///< per applied frame: largest point displacement / largest |F|
  double min_jacobian = 1.0;
  double max_miss = 0.0;
  double deepest = 0.0;                   ///< deepest a finger ended inside after a step (oracle, >= 0)
  std::uint32_t pca_probe_inside = 0;     ///< probe_inside by the PCA plane (diagnostic)
  std::uint32_t pca_passed_through = 0;   ///< passed_through by the PCA plane (diagnostic)
  double pca_deepest = 0.0;               ///< deepest by the PCA plane (diagnostic)
  std::uint32_t mesh_probe_inside = 0;    ///< probe_inside by the mesh, when the case has one
  std::uint32_t mesh_passed_through = 0;  ///< passed_through by the mesh, when the case has one
  double mesh_deepest = 0.0;              ///< deepest by the mesh, when the case has one
  bool judged_by_mesh = false;            ///< the case's mesh is closed and judges
  deform::GuardCounts guards;
};

class StrokeRunner {
 public:
  /// `base` is the model in case coordinates; it is mapped into `frame` for the deformer.
  /// `mesh`: the model's surface (index triples into its points, wound outward), or null; with
  /// one the mesh oracle judges every frame and the PCA plane's counts are diagnostics only.
  StrokeRunner(const deform::PointModel& base, const Outside& outside, const CaseSettings& settings,
               const Similarity& frame, const std::vector<std::uint32_t>* mesh = nullptr);
  StrokeRunner(const StrokeRunner&) = delete;
  StrokeRunner& operator=(const StrokeRunner&) = delete;

  /// Puts the fingers at `positions` (their accepted positions) without a frame: a stroke's start.
  void place(std::span<const deform::Vec3> positions);
  /// One frame: each finger moves from its accepted position to its target (base coordinates,
  /// one per placed finger); afterwards the accepted position is the probe after the frame.
  void press(std::span<const deform::Vec3> targets);

  /// The oracle's plane at q on the model as it is now (base coordinates and units).
  PlaneSide surface(const deform::Vec3& q);
  /// The mesh oracle's side of q on the model as it is now (base units); the runner must have a
  /// mesh.
  MeshSide mesh_surface(const deform::Vec3& q);
  bool has_mesh() const { return mesh_oracle_.has_value(); }
  /// Model point i now, in base coordinates.
  deform::Vec3 point(std::size_t i) const { return frame_.unapply(model_.position(i)); }
  const deform::Vec3& finger(std::size_t f) const { return fingers_[f].accepted; }

  double spacing() const { return spacing_; }  ///< base units
  double delta_d() const { return delta_d_; }  ///< base units
  const deform::PointModel& model() const { return model_; }
  const Metrics& metrics() const { return metrics_; }

 private:
  struct Finger {
    deform::Vec3 accepted;
    std::optional<deform::Vec3> earlier;
    // The mesh oracle's side of `accepted` on the model as the last frame left it, which is the
    // model the next frame starts from: a third of the mesh queries saved. Unset after place().
    std::optional<double> mesh_side;
  };
  static deform::DeformSettings settings_for(const deform::PointModel& model, const CaseSettings& s);
  bool model_finite() const;

  Similarity frame_;
  Outside outside_;  // in the model's frame
  deform::PointModel model_;
  deform::PointModel reference_;  // model_ before the stroke, for the oracle's orientation
  deform::Deformer deformer_;
  // SCULPT_CHECK_TRACE set: every finger of every step on stderr, with the deformer's normal at
  // the nearest point next to the oracle's, to see where the two disagree.
  bool trace_ = false;
  SurfaceSideOracle oracle_;
  std::optional<MeshSideOracle> mesh_oracle_;
  double spacing_ = 0.0, delta_d_ = 0.0;
  std::vector<Finger> fingers_;
  std::vector<deform::ProbeMotion> motions_;
  // Per finger, before the frame: the target's side and the accepted position's, by the PCA plane
  // and by the mesh (when the case has one).
  std::vector<double> side_before_, previous_side_, mesh_before_, mesh_previous_;
  Metrics metrics_;
};

}  // namespace sculpt::tools::check
