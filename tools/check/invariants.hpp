#pragma once
// The physical invariances a deformation must have, stated without the deformer's help: a
// similarity transform of model and probes together (rotation, scale, shift) must carry the
// result along, and G must cancel from positions. The sweep runs a case twice and compares.

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::tools::check {

/// p -> scale R p + shift, with R a rotation.
struct Similarity {
  double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  double scale = 1.0;
  deform::Vec3 shift;

  deform::Vec3 rotate(const deform::Vec3& v) const;
  deform::Vec3 unrotate(const deform::Vec3& v) const;  ///< R^T v
  deform::Vec3 apply(const deform::Vec3& p) const { return rotate(p) * scale + shift; }
  deform::Vec3 unapply(const deform::Vec3& p) const { return unrotate(p - shift) * (1.0 / scale); }
  /// this after `inner`: p -> this(inner(p)).
  Similarity after(const Similarity& inner) const;

  static Similarity scaling(double s);
  /// Rotation by `angle` radians about `axis` (Rodrigues), then the shift.
  static Similarity rigid(const deform::Vec3& axis, double angle, const deform::Vec3& shift);
};

/// The model with every point mapped and every normal rotated.
deform::PointModel transformed(const deform::PointModel& model, const Similarity& t);

/// Worst deviation of the displacements of `variant` (a run in the frame `t`, from
/// `variant_initial`) from those of `base` (the same run in the identity frame, from
/// `initial`), mapped back, relative to the largest base displacement or `floor`, whichever is
/// larger. Displacements rather than positions, so that rounding the transformed model to float
/// does not count; the floor keeps a few float ulps of the coordinates from counting as a
/// deviation when (almost) nothing moved.
double relative_deviation(const deform::PointModel& initial, const deform::PointModel& base,
                          const deform::PointModel& variant_initial, const deform::PointModel& variant,
                          const Similarity& t, double floor);

/// Largest |coordinate| of the model, in the units of the frame `t` maps from.
double coordinate_magnitude(const deform::PointModel& model, const Similarity& t);

}  // namespace sculpt::tools::check
