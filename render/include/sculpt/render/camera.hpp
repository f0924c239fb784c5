#pragma once
// Where the picture is taken from: a pinhole camera aimed at the model, fitted to its bounding
// box from a direction given as azimuth and elevation about an up axis, or as a vector.

#include <array>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::render {

using deform::Vec3;

/// Which model axis points up in the picture. Scans differ: the Stanford models are y-up, the
/// station's sphere scenes press along the z = 0 equator and read best z-up.
enum class UpAxis { kX, kY, kZ };

/// An axis-aligned box; empty (min > max) until a point is added.
struct Bounds {
  Vec3 min{1.0, 1.0, 1.0};
  Vec3 max{-1.0, -1.0, -1.0};

  bool empty() const { return min.x > max.x; }
  void add(const Vec3& p);
  void add(const Bounds& other);
  Vec3 centre() const { return 0.5 * (min + max); }
};

Bounds bounds_of(const deform::PointModel& model);
/// The largest distance from `centre` to a point of `model` (0 for an empty model): with the
/// bounding box's centre, the radius of a sphere around the model that is tight for round
/// models, where the box's half diagonal would be sqrt(3) times too large.
double farthest_distance(const deform::PointModel& model, const Vec3& centre);

/// The right-handed frame a view direction is measured in: for up = y, front is +z and right
/// is +x; for up = z, front is -y and right is +x; for up = x, front is -z and right is +y
/// (in every case cross(right, up) = front).
struct AxisFrame {
  Vec3 right, up, front;
};
AxisFrame axis_frame(UpAxis up);

/// The direction the camera looks in (from the eye toward the model) for an eye at `azimuth_deg`
/// about the up axis (0 = in front, positive toward the right) and `elevation_deg` above the
/// horizontal plane (90 = looking straight down).
Vec3 look_direction(UpAxis up, double azimuth_deg, double elevation_deg);

/// A pinhole camera: eye, target and up vector (not necessarily orthogonal to the view; it only
/// fixes the roll), vertical field of view, clip distances and the picture's size in pixels.
struct Camera {
  Vec3 eye;
  Vec3 target;
  Vec3 up;
  double vertical_fov_deg = 30.0;
  double near_distance = 0.01;
  double far_distance = 100.0;
  int width = 0;
  int height = 0;

  /// The eye's orthonormal frame: right, true up, and back (from the target toward the eye),
  /// so that (right, up, back) is right-handed like OpenGL's eye space.
  void basis(Vec3& right, Vec3& true_up, Vec3& back) const;
  /// Column-major 4x4 matrices for OpenGL: world to eye, and eye to clip space.
  std::array<double, 16> view_matrix() const;
  std::array<double, 16> projection_matrix() const;
  /// Pixels per model unit at unit distance in front of the eye (the focal length in pixels).
  double focal_pixels() const;
};

/// The camera that looks along `direction` at `centre` from just far enough away that the sphere
/// of `radius` around it fills the picture's narrower field of view, with `margin` (> 1) to
/// spare. Throws std::invalid_argument when the centre or direction is not finite, the
/// direction is zero, the radius is negative, or a size is not positive.
Camera fit_camera(const Vec3& centre, double radius, const Vec3& direction, UpAxis up, int width, int height,
                  double margin = 1.15);

/// `camera` moved, keeping its direction, so that `points` fill its picture: shifted sideways to
/// centre their projection and brought as close as lets them fit with `margin` to spare, but
/// never inside the sphere of `radius` about `camera.target` (so no point falls behind the eye).
/// A bounding-sphere fit leaves an elongated model (a dragon) small in a corner of the frame.
/// A few fixed-point rounds, since moving a perspective camera changes every projection.
Camera tighten(const Camera& camera, const std::vector<Vec3>& points, double radius, double margin = 1.1);

}  // namespace sculpt::render
