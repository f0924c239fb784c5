#pragma once
// Deformation settings checked against the model they will act on: lengths and positions so far
// beyond the model's size that they can only be typos or hostile input, and whose squares would
// overflow float alongside the model's coordinates.

#include <string>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

/// A length compared against the model, or a probe's distance from the model's centre, may be
/// at most this many bounding-box diagonals: far beyond any meaningful setting.
inline constexpr double kMaxDiagonals = 1e3;

/// The model's size as the range checks see it.
struct ModelExtent {
  Vec3 centre;            ///< centre of the axis-aligned bounding box
  double diagonal = 0.0;  ///< its diagonal length

  /// The extent of a non-empty model (an empty one has centre 0 and diagonal 0).
  static ModelExtent of(const PointModel& model);
};

/// Whether a length may be zero (meaning "off") or must be positive.
enum class LengthRule { kPositive, kNonNegative };

/// Throws std::invalid_argument "<name> = <value> ..." unless `value` is finite, > 0 (or >= 0
/// for kNonNegative) and at most kMaxDiagonals bounding-box diagonals.
void check_length_against_model(const std::string& name, double value, LengthRule rule, const ModelExtent& extent);

/// Throws std::invalid_argument "<name> ..." unless `position` is finite and within kMaxDiagonals
/// bounding-box diagonals of the model's centre.
void check_position_against_model(const std::string& name, const Vec3& position, const ModelExtent& extent);

/// What the user calls each length of DeformSettings where it was given (a command-line option,
/// a scene key), so a message names what to change.
struct SettingNames {
  std::string bc_radius = "bc radius";
  std::string min_source_distance = "minimum source distance";
  std::string guard_distance = "guard distance";
  std::string region_radius = "region radius";
  std::string border_width = "region border width";
  std::string regularization = "kernel regularization";
};

/// Checks every length of `settings` that is compared against the model (bc radius, Δd, Δr, the
/// region's radius when it has one, its border width, the regularized kernel's radius) with
/// check_length_against_model, naming it as `names` says. Δr and the border width may be 0.
/// @throw std::invalid_argument naming the first setting out of range.
void check_settings_against_model(const DeformSettings& settings, const PointModel& model,
                                  const SettingNames& names = {});

}  // namespace sculpt::deform
