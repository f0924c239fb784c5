#include "sculpt/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sculpt::render {
namespace {

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

}  // namespace

void Bounds::add(const Vec3& p) {
  if (empty()) {
    min = max = p;
    return;
  }
  for (int a = 0; a < 3; ++a) {
    min[a] = std::min(min[a], p[a]);
    max[a] = std::max(max[a], p[a]);
  }
}

void Bounds::add(const Bounds& other) {
  if (other.empty()) return;
  add(other.min);
  add(other.max);
}

Bounds bounds_of(const deform::PointModel& model) {
  Bounds b;
  for (std::size_t i = 0; i < model.size(); ++i) b.add(model.position(i));
  return b;
}

double farthest_distance(const deform::PointModel& model, const Vec3& centre) {
  double farthest = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) farthest = std::max(farthest, squared_norm(model.position(i) - centre));
  return std::sqrt(farthest);
}

AxisFrame axis_frame(UpAxis up) {
  switch (up) {
    case UpAxis::kX: return {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}};
    case UpAxis::kY: return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    case UpAxis::kZ: return {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}};
  }
  return {};
}

Vec3 look_direction(UpAxis up, double azimuth_deg, double elevation_deg) {
  const AxisFrame f = axis_frame(up);
  const double az = radians(azimuth_deg), el = radians(elevation_deg);
  // The eye sits along this unit vector from the target; the camera looks the other way.
  const Vec3 toward_eye = std::cos(el) * (std::cos(az) * f.front + std::sin(az) * f.right) + std::sin(el) * f.up;
  return -toward_eye;
}

void Camera::basis(Vec3& right, Vec3& true_up, Vec3& back) const {
  back = normalized(eye - target);
  right = normalized(cross(up, back));
  if (squared_norm(right) == 0.0) {
    // Looking straight along `up`: any roll will do, so take the axis least aligned with it.
    const Vec3 a = std::abs(back.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    right = normalized(cross(a, back));
  }
  true_up = cross(back, right);
}

std::array<double, 16> Camera::view_matrix() const {
  Vec3 r, u, b;
  basis(r, u, b);
  // Rows are the eye frame's axes; the translation takes the eye to the origin.
  return {r.x, u.x, b.x, 0.0,  //
          r.y, u.y, b.y, 0.0,  //
          r.z, u.z, b.z, 0.0,  //
          -dot(r, eye), -dot(u, eye), -dot(b, eye), 1.0};
}

std::array<double, 16> Camera::projection_matrix() const {
  const double f = 1.0 / std::tan(radians(vertical_fov_deg) / 2.0);
  const double aspect = static_cast<double>(width) / height;
  const double n = near_distance, fa = far_distance;
  return {f / aspect, 0.0, 0.0, 0.0,  //
          0.0, f, 0.0, 0.0,           //
          0.0, 0.0, (fa + n) / (n - fa), -1.0,
          0.0, 0.0, 2.0 * fa * n / (n - fa), 0.0};
}

double Camera::focal_pixels() const { return 0.5 * height / std::tan(radians(vertical_fov_deg) / 2.0); }

Camera fit_camera(const Vec3& centre, double radius, const Vec3& direction, UpAxis up, int width, int height,
                  double margin) {
  if (!is_finite(centre) || !(radius >= 0.0) || !std::isfinite(radius)) {
    throw std::invalid_argument("cannot fit a camera to a model without a finite centre and size");
  }
  if (!is_finite(direction) || squared_norm(direction) == 0.0) {
    throw std::invalid_argument("the view direction must be a finite, nonzero vector");
  }
  if (width <= 0 || height <= 0) throw std::invalid_argument("the picture size must be positive");
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.up = axis_frame(up).up;
  camera.target = centre;
  // A model may be a single point; give it some size to look at.
  radius = std::max(radius, 1e-9 * (1.0 + norm(centre)));
  const double half_v = radians(camera.vertical_fov_deg) / 2.0;
  const double half_h = std::atan(std::tan(half_v) * width / height);
  // The bounding sphere's silhouette subtends asin(radius / distance) from the eye.
  const double distance = margin * radius / std::sin(std::min(half_v, half_h));
  camera.eye = camera.target - distance * normalized(direction);
  camera.near_distance = std::max(distance - 1.5 * radius, 1e-3 * distance);
  camera.far_distance = distance + 1.5 * radius;
  return camera;
}

}  // namespace sculpt::render
