#pragma once
// Displacement as colour: how far each point moved between two versions of one model, and the
// colour scale that shows it.

#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/render/image.hpp"

namespace sculpt::render {

/// |after_i - before_i| for every point. Points are paired by index, which is what deformation
/// keeps; throws std::invalid_argument naming both counts when they differ.
std::vector<double> displacement_magnitudes(const deform::PointModel& before, const deform::PointModel& after);

/// The heat scale at t in [0, 1] (clamped): cool blue-grey (unmoved) through pale yellow and
/// orange to red (the largest displacement). Red is reached only at the top, and the hue
/// turns one way along the scale, so the hottest pixels stay recognisable after shading
/// (which scales all three channels alike).
Rgb heat_color(double t);

/// heat_color(value / max) per value; all cool when max <= 0.
std::vector<Rgb> heat_colors(const std::vector<double>& values, double max);

}  // namespace sculpt::render
