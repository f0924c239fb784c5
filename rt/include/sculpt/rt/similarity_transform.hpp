#pragma once
// Registration of the glove frame to the model frame: a similarity x -> s R x + t (uniform
// scale, proper rotation, translation), and its calibration from landmark pairs by Umeyama's
// closed form.

#include <array>
#include <span>

namespace sculpt::rt {

/// A rotation as a quaternion w + xi + yj + zk. Need not be exactly unit (see
/// SimilarityTransform::from_scale_rotation_translation).
struct Quaternion {
  double w = 1.0;
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

/// A rotation by `angle` radians about `axis` (right-handed; the axis need not be unit).
struct AxisAngle {
  std::array<double, 3> axis{0.0, 0.0, 1.0};
  double angle = 0.0;
};

/// A 3x3 matrix stored by rows: m[row][column].
using Matrix3 = std::array<std::array<double, 3>, 3>;

/// x -> s R x + t with s > 0 and R a proper rotation. Copyable plain data; apply() and the
/// algebra are noexcept; the factories validate.
class SimilarityTransform {
 public:
  /// How far a quaternion's norm may be from 1 and still be accepted (then normalised).
  static constexpr double kUnitTolerance = 1e-6;
  /// How far R^T R may be from I (largest entry) and det R from 1 for a given matrix.
  static constexpr double kOrthonormalTolerance = 1e-9;

  /// The identity.
  SimilarityTransform() noexcept = default;

  /// @throw std::invalid_argument for a non-finite value, scale <= 0, or a quaternion whose
  ///        norm differs from 1 by more than kUnitTolerance (within it, it is normalised).
  static SimilarityTransform from_scale_rotation_translation(double scale, const Quaternion& rotation,
                                                             const std::array<double, 3>& translation);
  /// @throw std::invalid_argument for a non-finite value, scale <= 0, or a zero axis with a
  ///        non-zero angle.
  static SimilarityTransform from_scale_rotation_translation(double scale, const AxisAngle& rotation,
                                                             const std::array<double, 3>& translation);
  /// @throw std::invalid_argument for a non-finite value, scale <= 0, or a matrix that is not
  ///        a proper rotation within kOrthonormalTolerance (a reflection included).
  static SimilarityTransform from_scale_rotation_translation(double scale, const Matrix3& rotation,
                                                             const std::array<double, 3>& translation);

  /// s R p + t.
  std::array<double, 3> apply(const std::array<double, 3>& point) const noexcept;
  /// s R v: a displacement or direction, no translation.
  std::array<double, 3> apply_vector(const std::array<double, 3>& vector) const noexcept;

  /// The transform that applies `first`, then this one: x -> this(first(x)).
  SimilarityTransform compose(const SimilarityTransform& first) const noexcept;
  /// x -> (1/s) R^T (x - t).
  SimilarityTransform inverse() const noexcept;

  double scale() const noexcept { return scale_; }
  const Matrix3& rotation() const noexcept { return rotation_; }
  const std::array<double, 3>& translation() const noexcept { return translation_; }
  /// The rotation as a unit quaternion with w >= 0.
  Quaternion quaternion() const noexcept;

 private:
  SimilarityTransform(double scale, const Matrix3& rotation, const std::array<double, 3>& translation) noexcept
      : scale_(scale), rotation_(rotation), translation_(translation) {}

  double scale_ = 1.0;
  Matrix3 rotation_{{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
  std::array<double, 3> translation_{0.0, 0.0, 0.0};
};

/// this(first(x)).
inline SimilarityTransform operator*(const SimilarityTransform& second, const SimilarityTransform& first) noexcept {
  return second.compose(first);
}

/// A calibration and how well it fits its landmarks (model units).
struct Calibration {
  SimilarityTransform transform;  ///< glove frame -> model frame
  double rms_residual = 0.0;      ///< sqrt(mean |model_i - transform(glove_i)|^2)
  double max_residual = 0.0;      ///< max |model_i - transform(glove_i)|
};

/// The least-squares similarity mapping `glove[i]` onto `model[i]` (Umeyama 1991, closed form
/// by SVD of the cross-covariance, with the sign fix that keeps the rotation proper when the
/// best orthogonal fit would be a reflection). Set-up only: allocates.
/// @throw std::invalid_argument for fewer than 3 pairs, sizes that differ, a non-finite
///        coordinate, or landmarks that are coincident or collinear (in either frame), which
///        leave the rotation undetermined.
Calibration calibrate_umeyama(std::span<const std::array<double, 3>> glove,
                              std::span<const std::array<double, 3>> model);

}  // namespace sculpt::rt
