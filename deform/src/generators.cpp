#include "sculpt/deform/generators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sculpt::deform {
namespace {

// Keeps a mistyped spacing from asking for billions of points.
constexpr double kMaxGeneratedPoints = 1e9;

void require_positive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("generator: ") + what + " must be positive and finite");
  }
}

void require_reasonable_count(double count) {
  if (count > kMaxGeneratedPoints) {
    // %g: std::to_string printed "10000000000.000000 points".
    char text[160];
    std::snprintf(text, sizeof text,
                  "generator: %g points requested, more than the %g a generator makes (a spacing or a count "
                  "mistyped?)",
                  count, kMaxGeneratedPoints);
    throw std::invalid_argument(text);
  }
}

}  // namespace

PointModel make_sphere(std::size_t n, double radius, const Vec3& centre) {
  require_positive(radius, "sphere radius");
  require_reasonable_count(static_cast<double>(n));
  // The golden angle makes successive points' longitudes as irrational as possible, so no
  // spiral arms line up; equal steps in height give equal areas (Archimedes' hat-box theorem).
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  PointModel model;
  model.resize(n, /*with_normals=*/true, /*with_colors=*/false);
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(n);
    const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden_angle * static_cast<double>(i);
    const Vec3 unit{ring * std::cos(phi), ring * std::sin(phi), z};
    model.set_position(i, centre + radius * unit);
    model.set_normal(i, unit);
  }
  return model;
}

PointModel make_plane_patch(std::size_t per_side, double spacing) {
  require_positive(spacing, "plane spacing");
  const double side = static_cast<double>(per_side);
  require_reasonable_count(side * side);
  PointModel model;
  model.resize(per_side * per_side, /*with_normals=*/true, /*with_colors=*/false);
  const double half = 0.5 * (side - 1.0);
  std::size_t i = 0;
  for (std::size_t row = 0; row < per_side; ++row) {
    for (std::size_t col = 0; col < per_side; ++col, ++i) {
      model.set_position(
          i, {(static_cast<double>(col) - half) * spacing, (static_cast<double>(row) - half) * spacing, 0.0});
      model.set_normal(i, {0.0, 0.0, 1.0});
    }
  }
  return model;
}

PointModel make_box(const Vec3& size, double spacing) {
  require_positive(size.x, "box size x");
  require_positive(size.y, "box size y");
  require_positive(size.z, "box size z");
  require_positive(spacing, "box spacing");
  // Intervals per axis; the grid is stretched to fit the edge exactly so opposite faces and
  // shared edges line up with no sliver row.
  std::size_t m[3];
  double step[3];
  double count_all = 1.0;
  double count_inside = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double intervals = std::max(1.0, std::round(size[a] / spacing));
    require_reasonable_count(intervals);
    m[a] = static_cast<std::size_t>(intervals);
    step[a] = size[a] / intervals;
    count_all *= intervals + 1.0;
    count_inside *= intervals - 1.0;
  }
  require_reasonable_count(count_all);
  const auto count = static_cast<std::size_t>(count_all - count_inside);
  const Vec3 low = -0.5 * size;

  PointModel model;
  model.x.reserve(count);
  model.y.reserve(count);
  model.z.reserve(count);
  model.nx.reserve(count);
  model.ny.reserve(count);
  model.nz.reserve(count);
  auto coordinate = [&](int a, std::size_t k) {
    // The far face is placed at exactly +size/2 rather than accumulated, so it mirrors the near
    // face bit for bit.
    return k == m[a] ? 0.5 * size[a] : low[a] + static_cast<double>(k) * step[a];
  };
  auto face_side = [&](int a, std::size_t k) { return k == 0 ? -1.0 : (k == m[a] ? 1.0 : 0.0); };

  for (std::size_t k = 0; k <= m[2]; ++k) {
    for (std::size_t j = 0; j <= m[1]; ++j) {
      const bool on_zy = k == 0 || k == m[2] || j == 0 || j == m[1];
      // Inside the box along y and z only the two x faces are surface: jump straight across.
      const std::size_t i_step = on_zy ? 1 : m[0];
      for (std::size_t i = 0; i <= m[0]; i += i_step) {
        const Vec3 p{coordinate(0, i), coordinate(1, j), coordinate(2, k)};
        const Vec3 n = normalized(Vec3{face_side(0, i), face_side(1, j), face_side(2, k)});
        model.x.push_back(static_cast<float>(p.x));
        model.y.push_back(static_cast<float>(p.y));
        model.z.push_back(static_cast<float>(p.z));
        model.nx.push_back(static_cast<float>(n.x));
        model.ny.push_back(static_cast<float>(n.y));
        model.nz.push_back(static_cast<float>(n.z));
      }
    }
  }
  return model;
}

}  // namespace sculpt::deform
