#pragma once
// A point model made ready to draw: normals (from the file, its faces, or estimated), one base
// colour per point, and, for a model without faces, the splat size that closes the gaps
// between neighbouring points so a dense scan reads as a surface.

#include <cstdint>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"

namespace sculpt::render {

/// Splat diameter as a multiple of a point's local spacing (the distance to its third nearest
/// distinct neighbour): below about 1.4 a near-uniform scan shows the background between its
/// points, and a scan's sparse patches need their own, larger splats.
inline constexpr double kSplatsPerSpacing = 1.5;

/// Points whose splats share one size (OpenGL's fixed pipeline has one point size per draw).
struct SplatClass {
  double diameter = 0.0;  ///< model units
  std::vector<std::uint32_t> points;
};

/// The colour of a model that has none of its own: a light clay, so shading reads clearly.
inline constexpr Rgb kClayColor{0.80, 0.74, 0.66};

class RenderModel {
 public:
  /// Copies what drawing needs from `model`. Normals come from the model when it has them,
  /// else from its faces, else by PCA (deform::ensure_normals). Colours are the model's, or
  /// kClayColor. Throws std::invalid_argument for an empty model or one without a length scale
  /// (all points coincide) when it has no faces to draw.
  explicit RenderModel(const deform::PointModel& model);

  /// The same model after a deformation: takes its positions and normals (recomputed as the
  /// constructor does when it has none), keeps the colours, and sizes each splat again from the
  /// neighbours the build found for it, where they are now: a stretch widens the splats it
  /// opens gaps between. Finding every point's neighbours anew costs far more (0.41-0.48 s
  /// for 437,645 points here), so a live view calls this for every frame and builds anew once
  /// the model is still (neighbours that were not the nearest at the build are not seen here).
  /// Throws std::invalid_argument when the point count is not this model's.
  void follow(const deform::PointModel& model);

  /// Replaces the base colours (one per point; e.g. a heat map). Throws std::invalid_argument
  /// when the count is not the model's.
  void set_colors(const std::vector<Rgb>& colors);

  std::size_t size() const { return positions_.size() / 3; }
  bool has_faces() const { return !triangles_.empty(); }
  /// The splats by size, smallest first (empty when the model is drawn as faces).
  const std::vector<SplatClass>& splat_classes() const { return splat_classes_; }
  /// The largest splat diameter in model units (0 when the model is drawn as faces).
  double largest_splat_diameter() const { return splat_classes_.empty() ? 0.0 : splat_classes_.back().diameter; }

  const std::vector<float>& positions() const { return positions_; }  ///< x, y, z per point
  const std::vector<float>& normals() const { return normals_; }      ///< unit, x, y, z per point
  const std::vector<float>& colors() const { return colors_; }        ///< r, g, b in [0, 1] per point
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }

 private:
  void take_positions(const deform::PointModel& model);
  void take_normals(const deform::PointModel& model);

  std::vector<float> positions_, normals_, colors_;
  std::vector<std::uint32_t> triangles_;
  std::vector<SplatClass> splat_classes_;
  // For a model drawn as splats: each point's nearest distinct neighbours at the build, three
  // per point, and the build's typical spacing, which the classes' sizes are quarter octaves of.
  std::vector<std::uint32_t> splat_neighbours_;
  double typical_spacing_ = 0.0;
};

}  // namespace sculpt::render
