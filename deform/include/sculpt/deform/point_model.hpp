#pragma once
// The point cloud every other part of deform works on.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

/// Coordinates must be finite and below this in magnitude: a difference of two is then below
/// 2e18 and a squared distance below 1.2e37, finite even in float (FLT_MAX is 3.4e38).
inline constexpr double kMaxCoordinate = 1e18;

/// A point cloud stored as structure of arrays: each attribute is one contiguous float (or
/// byte) array, so the deformation loops read and write them with aligned SIMD lanes and no
/// gathers. Optional attributes are empty arrays when the model does not have them; a model
/// "has normals" exactly when nx, ny and nz hold one entry per point.
struct PointModel {
  std::vector<float> x, y, z;
  /// Unit normals, or empty. Straight from a file they are as the file has them; check_normals()
  /// (normal_check.hpp) makes them unit or refuses them.
  std::vector<float> nx, ny, nz;
  std::vector<std::uint8_t> red, green, blue, alpha;  ///< colours, or empty (alpha may be empty alone)
  /// Triangles from the file (three point indices each; polygons are fanned), or empty. The
  /// connectivity of the surface: deformation moves the points and leaves it as it is, and the
  /// PLY and OFF writers write it back, so mesh tools show the sculpted surface.
  std::vector<std::uint32_t> triangles;

  std::size_t size() const { return x.size(); }
  bool empty() const { return x.empty(); }
  bool has_normals() const { return !nx.empty(); }
  bool has_colors() const { return !red.empty(); }
  bool has_alpha() const { return !alpha.empty(); }

  Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  Vec3 normal(std::size_t i) const { return {nx[i], ny[i], nz[i]}; }
  void set_position(std::size_t i, const Vec3& p);
  void set_normal(std::size_t i, const Vec3& n);

  /// Resizes every present attribute to n points; adds normals or colours when asked.
  void resize(std::size_t n, bool with_normals, bool with_colors, bool with_alpha = false);
  /// Appends a point; normals/colours must match what the model has (unset ones are zero).
  void push_back(const Vec3& p);
  void clear_normals();

  /// Throws std::invalid_argument naming the attribute when array sizes disagree, a triangle
  /// index is out of range, or a coordinate is not finite or not below kMaxCoordinate in
  /// magnitude (naming the point).
  void validate() const;

  /// The axis-aligned bounding box's lowest and highest corner (both the origin for an empty model).
  struct Box {
    Vec3 lo, hi;
  };
  Box bounding_box() const noexcept;
  /// Axis-aligned bounding box diagonal length (0 for an empty model).
  double bounding_box_diagonal() const;
  /// Centre of the axis-aligned bounding box (the origin for an empty model).
  Vec3 bounding_box_centre() const;
};

}  // namespace sculpt::deform
