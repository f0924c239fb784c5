#pragma once
// The test's own camera maths, written from the pinhole model rather than from the renderer's
// matrices, so that a picture can be checked against where geometry says things must land.

#include <cmath>
#include <numbers>

#include "sculpt/render/camera.hpp"
#include "sculpt/render/image.hpp"

namespace sculpt::test {

using render::Vec3;

struct PixelPoint {
  double x = 0.0;  ///< pixels from the left edge (pixel i covers [i, i + 1))
  double y = 0.0;  ///< pixels from the top edge
};

/// Where `p` lands in `camera`'s picture: eye-frame coordinates by dot products with the
/// view's axes, then a perspective divide by the distance along the view axis.
inline PixelPoint project(const render::Camera& camera, const Vec3& p) {
  const Vec3 forward = deform::normalized(camera.target - camera.eye);
  const Vec3 right = deform::normalized(deform::cross(forward, camera.up));
  const Vec3 up = deform::cross(right, forward);
  const Vec3 v = p - camera.eye;
  const double depth = deform::dot(v, forward);
  const double focal = 0.5 * camera.height / std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0);
  return {0.5 * camera.width + focal * deform::dot(v, right) / depth,
          0.5 * camera.height - focal * deform::dot(v, up) / depth};
}

/// Radius in pixels of the disc a sphere of `radius` at `centre` makes when the camera looks at
/// its centre: its silhouette cone has half-angle asin(radius / distance).
inline double projected_sphere_radius(const render::Camera& camera, const Vec3& centre, double radius) {
  const double distance = deform::norm(centre - camera.eye);
  const double half_angle = std::asin(radius / distance);
  return std::tan(half_angle) / std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0) * 0.5 * camera.height;
}

inline double luminance(const render::Image& image, int x, int y) {
  const std::uint8_t* p = image.at(x, y);
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

inline bool same_color(const render::Image& image, int x, int y, const render::Rgb& c, int tolerance = 2) {
  const std::uint8_t* p = image.at(x, y);
  return std::abs(p[0] - render::to_byte(c.r)) <= tolerance && std::abs(p[1] - render::to_byte(c.g)) <= tolerance &&
         std::abs(p[2] - render::to_byte(c.b)) <= tolerance;
}

}  // namespace sculpt::test
