#include "sculpt/render/heat_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sculpt::render {
namespace {

struct Stop {
  double t;
  Rgb color;
};

// Hue falls monotonically from blue-grey to red along the stops; the cool end is muted so the
// unmoved part of a model still reads as a shaded surface.
constexpr std::array<Stop, 5> kStops{{{0.00, {0.45, 0.55, 0.80}},
                                      {0.25, {0.45, 0.75, 0.80}},
                                      {0.50, {0.75, 0.85, 0.45}},
                                      {0.75, {0.98, 0.65, 0.20}},
                                      {1.00, {0.85, 0.10, 0.10}}}};

}  // namespace

std::vector<double> displacement_magnitudes(const deform::PointModel& before, const deform::PointModel& after) {
  if (before.size() != after.size()) {
    throw std::invalid_argument("the models have " + std::to_string(before.size()) + " and " +
                                std::to_string(after.size()) +
                                " points; displacement pairs points by index, so both must be versions of one model");
  }
  std::vector<double> magnitudes(after.size());
  for (std::size_t i = 0; i < after.size(); ++i) magnitudes[i] = norm(after.position(i) - before.position(i));
  return magnitudes;
}

Rgb heat_color(double t) {
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 1.0;
  std::size_t k = 1;
  while (k + 1 < kStops.size() && t > kStops[k].t) ++k;
  const Stop& a = kStops[k - 1];
  const Stop& b = kStops[k];
  const double u = (t - a.t) / (b.t - a.t);
  return {a.color.r + u * (b.color.r - a.color.r), a.color.g + u * (b.color.g - a.color.g),
          a.color.b + u * (b.color.b - a.color.b)};
}

std::vector<Rgb> heat_colors(const std::vector<double>& values, double max) {
  std::vector<Rgb> colors(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) colors[i] = heat_color(max > 0.0 ? values[i] / max : 0.0);
  return colors;
}

}  // namespace sculpt::render
