#pragma once
// The model's own length scale, from which scale-free defaults (bc radius, Δd, Δr) are derived.

#include <cstddef>

#include "sculpt/deform/point_index.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// Mean distance from a point to its nearest neighbour, over an even sample of at most
/// `samples` points (0 for fewer than two points).
double mean_spacing(const PointModel& model, const PointIndex& index, std::size_t samples = 2000);

}  // namespace sculpt::deform
