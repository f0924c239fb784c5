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
  for (std::size_t i = 0; i < model.size(); ++i)
    farthest = std::max(farthest, squared_norm(model.position(i) - centre));
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
  return {r.x,          u.x,          b.x,          0.0,  //
          r.y,          u.y,          b.y,          0.0,  //
          r.z,          u.z,          b.z,          0.0,  //
          -dot(r, eye), -dot(u, eye), -dot(b, eye), 1.0};
}

std::array<double, 16> Camera::projection_matrix() const {
  const double f = 1.0 / std::tan(radians(vertical_fov_deg) / 2.0);
  const double aspect = static_cast<double>(width) / height;
  const double n = near_distance, fa = far_distance;
  return {f / aspect,
          0.0,
          0.0,
          0.0,  //
          0.0,
          f,
          0.0,
          0.0,  //
          0.0,
          0.0,
          (fa + n) / (n - fa),
          -1.0,
          0.0,
          0.0,
          2.0 * fa * n / (n - fa),
          0.0};
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

Camera tighten(const Camera& camera, const std::vector<Vec3>& points, double radius, double margin) {
  constexpr int kRounds = 8;
  Camera c = camera;
  const Vec3 centre = camera.target;
  const double tan_v = std::tan(radians(c.vertical_fov_deg) / 2.0);
  const double tan_h = tan_v * c.width / c.height;
  for (int round = 0; round < kRounds && !points.empty(); ++round) {
    Vec3 right, up, back;
    c.basis(right, up, back);
    // The points' extent in tangent-of-angle coordinates, where the frame is [-tan_h, tan_h] x
    // [-tan_v, tan_v].
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (const Vec3& p : points) {
      const Vec3 v = p - c.eye;
      const double depth = -dot(v, back);
      if (!(depth > 0.0)) continue;
      const double x = dot(v, right) / depth, y = dot(v, up) / depth;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    if (!(x1 > x0) && !(y1 > y0)) break;
    const double distance = norm(c.target - c.eye);
    const Vec3 shift = distance * (0.5 * (x0 + x1) * right + 0.5 * (y0 + y1) * up);
    const double scale = margin * std::max((x1 - x0) / (2.0 * tan_h), (y1 - y0) / (2.0 * tan_v));
    c.target += shift;
    const double closer = std::max(distance * scale, 1.05 * radius + norm(c.target - centre));
    c.eye = c.target + closer * back;
    c.near_distance = std::max(closer - 1.5 * radius, 1e-3 * closer);
    c.far_distance = closer + 1.5 * radius;
  }
  return c;
}

}  // namespace sculpt::render
