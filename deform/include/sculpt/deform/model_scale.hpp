#pragma once
// The model's own length scale, from which scale-free defaults (bc radius, Δd, Δr, Δs, region
// radius) are derived.

#include <cstddef>
#include <string>

#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// A length scale and the statistic it came from, so that whoever prints a derived default can
/// say what it was derived from.
struct TypicalSpacing {
  double value = 0.0;
  std::string statistic;  ///< e.g. "median nearest-neighbour distance over distinct points, 2000 samples"
};

/// The median, over an even sample of at most `samples` points, of the distance from a point to
/// its nearest neighbour at a distance > 0. The median ignores stray vertices far from the
/// surface, and skipping coincident neighbours ignores duplicated points, either of which would
/// drag a mean (a single vertex at 1e4 on a unit sphere, or a fully duplicated file giving 0).
/// `index` must be built over `model`'s current positions.
/// @throw std::invalid_argument when there is no length scale: the model is empty or all its
///        points coincide (the message says which), `samples` is 0, or the index does not match.
TypicalSpacing typical_spacing(const PointModel& model, const PointIndex& index, std::size_t samples = 2000);

/// The median, over an even sample of at most 64 points, of how many points lie within
/// `radius` of a point (itself included): how many points a ball of that radius holds on the
/// model. 0 for an empty model. `index` must be built over `model`. Set-up work: allocates.
std::size_t median_ball_count(const PointModel& model, const PointIndex& index, double radius);

}  // namespace sculpt::deform
