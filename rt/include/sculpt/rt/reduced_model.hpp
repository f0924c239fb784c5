#pragma once
// The reduced model set of thesis 4.4.1 (MATH.md §5): sculpt a uniform subsample at
// interactive rates, then transfer the recorded frames to the full model offline; and the
// measure of how far the two results differ.

#include <cstdint>
#include <vector>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::rt {

/// How close to ratio x N the subsample's size must come before the voxel search stops.
inline constexpr double kReducedCountTolerance = 0.01;

/// Indices (ascending) of a uniform-density subsample of about ratio x full.size() points:
/// a voxel grid keeps, in each occupied voxel, the point nearest the voxel's centre, and the
/// voxel size is bisected until the count is within kReducedCountTolerance of the target (or
/// the closest count the search met). Regular density, not a random subset, because the
/// thesis needs the subsample to sample the surface evenly. ratio == 1 keeps every point.
/// Throws std::invalid_argument unless ratio is in (0, 1].
std::vector<std::uint32_t> reduced_indices(const deform::PointModel& full, double ratio);

/// The subsample of reduced_indices() as a model, with the normals and colours of the kept
/// points (triangles are dropped: their indices would not survive). ratio == 1 returns a copy.
deform::PointModel reduced_model(const deform::PointModel& full, double ratio);

/// Point-by-point difference of two models of the same size.
struct ModelDifference {
  double mean = 0.0;  ///< mean distance / bounding-box diagonal of the reference
  double max = 0.0;   ///< largest distance / bounding-box diagonal of the reference
};

/// Distances between corresponding points, relative to reference's bounding-box diagonal
/// (absolute when that diagonal is 0). Throws std::invalid_argument when the sizes differ.
ModelDifference compare_models(const deform::PointModel& reference, const deform::PointModel& other);

}  // namespace sculpt::rt
