// The camera's conventions (azimuth, elevation, up axes) and its OpenGL matrices against the
// pinhole model written out independently.
#include <gtest/gtest.h>

#include <array>

#include "render/pinhole.hpp"
#include "sculpt/render/camera.hpp"

namespace sculpt::test {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tolerance = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Camera, AzimuthAndElevationFollowTheUpAxis) {
  using render::UpAxis;
  // y up: the front is +z, so at azimuth 0 the camera looks along -z; at 90 the eye is at +x.
  expect_near(render::look_direction(UpAxis::kY, 0.0, 0.0), {0, 0, -1});
  expect_near(render::look_direction(UpAxis::kY, 90.0, 0.0), {-1, 0, 0});
  expect_near(render::look_direction(UpAxis::kY, 0.0, 90.0), {0, -1, 0});
  // z up: the front is -y (eye at -y looks along +y), azimuth 90 puts the eye at +x.
  expect_near(render::look_direction(UpAxis::kZ, 0.0, 0.0), {0, 1, 0});
  expect_near(render::look_direction(UpAxis::kZ, 90.0, 0.0), {-1, 0, 0});
  expect_near(render::look_direction(UpAxis::kZ, 0.0, 90.0), {0, 0, -1});
  for (const UpAxis up : {UpAxis::kX, UpAxis::kY, UpAxis::kZ}) {
    const render::AxisFrame f = render::axis_frame(up);
    expect_near(deform::cross(f.right, f.up), f.front);
  }
}

// A point through the view and projection matrices and the perspective divide must land
// where the pinhole model puts it.
TEST(Camera, MatricesAgreeWithThePinholeModel) {
  const render::Camera camera = render::fit_camera(
      {1.0, -2.0, 0.5}, 2.0, render::look_direction(render::UpAxis::kZ, 35, -20), render::UpAxis::kZ, 300, 200);
  const std::array<double, 16> view = camera.view_matrix(), projection = camera.projection_matrix();
  auto times = [](const std::array<double, 16>& m, const std::array<double, 4>& v) {
    std::array<double, 4> out{};
    for (int row = 0; row < 4; ++row) {
      for (int k = 0; k < 4; ++k) out[row] += m[k * 4 + row] * v[k];  // column-major
    }
    return out;
  };
  for (const Vec3 p : {Vec3{1.0, -2.0, 0.5}, Vec3{2.2, -1.1, 1.3}, Vec3{-0.4, -3.0, -0.9}}) {
    const std::array<double, 4> clip = times(projection, times(view, {p.x, p.y, p.z, 1.0}));
    const double x = (clip[0] / clip[3] + 1.0) * 0.5 * camera.width;
    const double y = (1.0 - clip[1] / clip[3]) * 0.5 * camera.height;
    const PixelPoint expected = project(camera, p);
    EXPECT_NEAR(x, expected.x, 1e-9);
    EXPECT_NEAR(y, expected.y, 1e-9);
    EXPECT_GT(clip[2] / clip[3], -1.0);  // between the clip planes
    EXPECT_LT(clip[2] / clip[3], 1.0);
  }
}

TEST(Camera, FitShowsTheWholeBoundingSphereWithTheMargin) {
  const render::Camera camera = render::fit_camera({0, 0, 0}, 1.0, {0, 0, -1}, render::UpAxis::kY, 400, 200);
  // The narrower field of view is the vertical one here; the silhouette's half-angle a has
  // sin a = sin(half the field of view) / margin, and lands tan a / tan(half fov) of the way to
  // the top edge.
  const double half_fov = camera.vertical_fov_deg * std::numbers::pi / 360.0;
  const double silhouette = std::asin(std::sin(half_fov) / 1.15);
  EXPECT_NEAR(projected_sphere_radius(camera, {0, 0, 0}, 1.0), std::tan(silhouette) / std::tan(half_fov) * 100.0, 1e-9);
  EXPECT_LT(projected_sphere_radius(camera, {0, 0, 0}, 1.0), 100.0);
  EXPECT_THROW(render::fit_camera({0, 0, 0}, 1.0, {0, 0, 0}, render::UpAxis::kY, 10, 10), std::invalid_argument);
}

// Tightened on an elongated set of points, the camera keeps its direction and the points'
// projection is centred and fills the frame's limiting side, up to the margin.
TEST(Camera, TightenCentresAndFillsThePicture) {
  std::vector<Vec3> points;
  for (int i = 0; i <= 20; ++i) points.push_back({-2.0 + 0.2 * i, 0.3 * std::sin(i), 0.1 * i - 1.0});
  const double radius = 2.3;
  const Vec3 look = render::look_direction(render::UpAxis::kY, 20.0, 15.0);
  const render::Camera loose = render::fit_camera({0, 0, 0}, radius, look, render::UpAxis::kY, 320, 240);
  const render::Camera tight = render::tighten(loose, points, radius);
  EXPECT_NEAR(deform::dot(deform::normalized(tight.target - tight.eye), deform::normalized(look)), 1.0, 1e-12);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const Vec3& p : points) {
    const PixelPoint q = project(tight, p);
    x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
  }
  EXPECT_NEAR(0.5 * (x0 + x1), 160.0, 2.0);
  EXPECT_NEAR(0.5 * (y0 + y1), 120.0, 2.0);
  EXPECT_NEAR(std::max((x1 - x0) / 320.0, (y1 - y0) / 240.0), 1.0 / 1.1, 0.02);
  EXPECT_GT(x0, 0.0);
  EXPECT_LT(x1, 320.0);
}

}  // namespace
}  // namespace sculpt::test
