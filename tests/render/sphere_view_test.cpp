// A rendered sphere must be a disc of lit pixels exactly where the pinhole model puts it, and
// brightest where its normal faces the light.
#include <gtest/gtest.h>

#include <cmath>

#include "render/pinhole.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/render/lighting.hpp"
#include "sculpt/render/view_renderer.hpp"

namespace sculpt::test {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 160;
const Vec3 kCentre{0.3, -0.2, 0.5};
constexpr double kRadius = 0.8;

render::Lighting black_background() {
  render::Lighting lighting;
  lighting.background = {0.0, 0.0, 0.0};
  return lighting;
}

// Away from the view axis, so the test does not pass only for an axis-aligned camera.
render::Camera oblique_camera() {
  const Vec3 look = render::look_direction(render::UpAxis::kY, 40.0, 25.0);
  return render::fit_camera(kCentre, kRadius, look, render::UpAxis::kY, kWidth, kHeight);
}

TEST(SphereView, IsADiscOfLitPixelsWhereTheProjectionSays) {
  const render::RenderModel sphere(deform::make_sphere(20000, kRadius, kCentre));
  const render::Camera camera = oblique_camera();
  render::ViewRenderer renderer(kWidth, kHeight);
  const render::Image image = renderer.render(sphere, camera, black_background());

  const PixelPoint centre = project(camera, kCentre);
  const double radius = projected_sphere_radius(camera, kCentre, kRadius);
  ASSERT_GT(radius, 40.0);  // a disc big enough to measure
  // Splats reach at most half a splat (0.8 spacing, about 1 px here) past the silhouette, and
  // a supersampled edge pixel is partly covered: 2 px either side of the circle is the seam.
  int lit_inside = 0, inside = 0, lit_outside = 0;
  double sum_x = 0.0, sum_y = 0.0;
  int lit = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double r = std::hypot(x + 0.5 - centre.x, y + 0.5 - centre.y);
      const bool is_lit = luminance(image, x, y) > 10.0;
      if (is_lit) {
        sum_x += x + 0.5;
        sum_y += y + 0.5;
        ++lit;
      }
      if (r < radius - 2.0) {
        ++inside;
        lit_inside += is_lit;
      } else if (r > radius + 2.0) {
        lit_outside += is_lit;
      }
    }
  }
  EXPECT_EQ(lit_inside, inside) << "every pixel well inside the disc shows the sphere";
  EXPECT_EQ(lit_outside, 0) << "no pixel well outside it does";
  EXPECT_NEAR(sum_x / lit, centre.x, 0.5);
  EXPECT_NEAR(sum_y / lit, centre.y, 0.5);
  // The lit area is the silhouette's disc, widened by at most the half splat that rim points
  // reach past it.
  const double measured_radius = std::sqrt(lit / std::numbers::pi);
  const double half_splat_px = 0.5 * sphere.largest_splat_diameter() / kRadius * radius;
  EXPECT_GT(measured_radius, radius - 0.5);
  EXPECT_LT(measured_radius, radius + half_splat_px + 0.5);
}

// Lambert's law peaks where n . l = 1: at the sphere point centre + radius * l. The pixels
// within 2% of the brightest must gather around its projection, wherever the light is.
TEST(SphereView, IsBrightestWhereTheNormalFacesTheLight) {
  const render::RenderModel sphere(deform::make_sphere(20000, kRadius, kCentre));
  const render::Camera camera = oblique_camera();
  render::ViewRenderer renderer(kWidth, kHeight);
  for (const Vec3 light : {Vec3{-0.45, 0.55, 0.70}, Vec3{0.5, -0.2, 0.8}, Vec3{0.0, 0.0, 1.0}}) {
    render::Lighting lighting = black_background();
    lighting.light_in_camera = light;
    const render::Image image = renderer.render(sphere, camera, lighting);
    double brightest = 0.0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) brightest = std::max(brightest, luminance(image, x, y));
    }
    double sum_x = 0.0, sum_y = 0.0;
    int count = 0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        if (luminance(image, x, y) < 0.98 * brightest) continue;
        sum_x += x + 0.5;
        sum_y += y + 0.5;
        ++count;
      }
    }
    const Vec3 towards_light = render::light_direction(camera, lighting);
    const PixelPoint peak = project(camera, kCentre + kRadius * towards_light);
    const double radius = projected_sphere_radius(camera, kCentre, kRadius);
    ASSERT_GT(count, 0);
    EXPECT_NEAR(sum_x / count, peak.x, 0.08 * radius) << "light " << light.x << "," << light.y << "," << light.z;
    EXPECT_NEAR(sum_y / count, peak.y, 0.08 * radius) << "light " << light.x << "," << light.y << "," << light.z;
    // Full diffuse plus ambient of the clay colour at the peak, ambient alone facing away.
    EXPECT_GT(brightest, 0.9 * 255.0 * (lighting.ambient + lighting.diffuse) * 0.74);
  }
}

// The light is given in the camera's frame; in the world it must turn with the camera.
TEST(SphereView, LightFollowsTheCamera) {
  const render::Camera camera = oblique_camera();
  render::Lighting lighting;
  lighting.light_in_camera = {0.0, 0.0, 1.0};
  const Vec3 l = render::light_direction(camera, lighting);
  const Vec3 to_eye = deform::normalized(camera.eye - camera.target);
  EXPECT_NEAR(deform::dot(l, to_eye), 1.0, 1e-12);
}

}  // namespace
}  // namespace sculpt::test
