// The compare picture's heat map: its hottest pixels sit at the contact of a known dent, the
// before panel has none, and the colour scale and the pairing of points behave as documented.
#include <gtest/gtest.h>

#include <cmath>

#include "render/pinhole.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/render/heat_map.hpp"
#include "sculpt/render/picture.hpp"

namespace sculpt::test {
namespace {

constexpr int kView = 160;
constexpr double kDepth = 0.12;
constexpr double kDentAngle = 0.45;  // radians

// A sphere pressed in along `contact` (a unit vector): each point within kDentAngle of it moves
// inward along its normal by kDepth (1 - (angle / kDentAngle)^2)^2, deepest at the contact.
deform::PointModel dented(const deform::PointModel& sphere, const Vec3& contact) {
  deform::PointModel m = sphere;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 n = m.normal(i);
    const double angle = std::acos(std::clamp(deform::dot(n, contact), -1.0, 1.0));
    if (angle >= kDentAngle) continue;
    const double u = 1.0 - (angle / kDentAngle) * (angle / kDentAngle);
    m.set_position(i, m.position(i) - kDepth * u * u * n);
  }
  return m;
}

// Hue in degrees; shading scales all three channels alike, so it is the heat scale's own.
double hue(const std::uint8_t* p) {
  const double r = p[0], g = p[1], b = p[2];
  const double hi = std::max({r, g, b}), lo = std::min({r, g, b});
  if (hi - lo < 1e-9) return -1.0;
  double h = 0.0;
  if (hi == r)
    h = std::fmod((g - b) / (hi - lo), 6.0);
  else if (hi == g)
    h = (b - r) / (hi - lo) + 2.0;
  else
    h = (r - g) / (hi - lo) + 4.0;
  return h < 0 ? h * 60.0 + 360.0 : h * 60.0;
}

// Red and as saturated as the top tenth of the scale (the clay and anti-aliased edges are not).
bool hot(const std::uint8_t* p) {
  const double h = hue(p);
  const double saturation = 1.0 - static_cast<double>(std::min({p[0], p[1], p[2]})) / std::max<int>(1, p[0]);
  return h >= 0.0 && (h < 12.0 || h > 350.0) && p[0] > 40 && saturation > 0.6;
}

TEST(HeatMap, HottestPixelsSitAtTheDentsContact) {
  const deform::PointModel before = deform::make_sphere(12000, 1.0);
  const Vec3 contact = deform::normalized({0.3, 0.25, 1.0});
  const deform::PointModel after = dented(before, contact);

  render::PictureRequest request;
  request.view_width = request.view_height = kView;
  request.look = Vec3{-0.2, -0.1, -1.0};
  render::PictureInfo info;
  const render::Image picture = render::render_picture(after, &before, request, &info);
  EXPECT_NEAR(info.max_displacement, kDepth, 0.01 * kDepth);
  ASSERT_EQ(info.rows, 1);
  ASSERT_EQ(info.columns, 2);
  ASSERT_GT(picture.width, 2 * kView);  // before, after, colour bar
  ASSERT_EQ(picture.height, kView);

  // The camera the picture says it used; where the contact lands is the test's own projection.
  ASSERT_EQ(info.cameras.size(), 1u);
  const render::Camera& camera = info.cameras[0];
  EXPECT_NEAR(deform::dot(deform::normalized(camera.target - camera.eye), deform::normalized(*request.look)), 1.0,
              1e-9);
  const PixelPoint expected = project(camera, (1.0 - kDepth) * contact);
  double sum_x = 0.0, sum_y = 0.0;
  int hot_after = 0, hot_before = 0;
  for (int y = 0; y < kView; ++y) {
    for (int x = 0; x < kView; ++x) {
      hot_before += hot(picture.at(x, y));
      if (!hot(picture.at(kView + x, y))) continue;
      sum_x += x + 0.5;
      sum_y += y + 0.5;
      ++hot_after;
    }
  }
  EXPECT_EQ(hot_before, 0) << "the before panel is not coloured by displacement";
  ASSERT_GT(hot_after, 3);
  const double disc = projected_sphere_radius(camera, {0, 0, 0}, 1.0);
  EXPECT_NEAR(sum_x / hot_after, expected.x, 0.05 * disc);
  EXPECT_NEAR(sum_y / hot_after, expected.y, 0.05 * disc);
  // And the side away from the dent is cool: blue-grey, hue above 180 degrees.
  const PixelPoint away = project(camera, deform::normalized(Vec3{-0.4, -0.3, 0.8}));
  EXPECT_GT(hue(picture.at(kView + static_cast<int>(away.x), static_cast<int>(away.y))), 180.0);
}

TEST(HeatMap, PairsPointsByIndexAndRefusesDifferentCounts) {
  const deform::PointModel a = deform::make_sphere(100, 1.0);
  deform::PointModel b = a;
  b.set_position(7, b.position(7) + Vec3{0.0, 0.3, 0.4});
  const std::vector<double> d = render::displacement_magnitudes(a, b);
  EXPECT_NEAR(d[7], 0.5, 1e-6);
  EXPECT_EQ(d[8], 0.0);
  const deform::PointModel c = deform::make_sphere(99, 1.0);
  try {
    render::displacement_magnitudes(a, c);
    FAIL() << "different point counts were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("100 and 99 points"), std::string::npos) << e.what();
  }
}

TEST(HeatMap, HueTurnsOneWayFromCoolToRed) {
  double previous = 360.0;
  for (int i = 0; i <= 100; ++i) {
    const render::Rgb c = render::heat_color(i / 100.0);
    const std::uint8_t p[3] = {render::to_byte(c.r), render::to_byte(c.g), render::to_byte(c.b)};
    double h = hue(p);
    if (h > 350.0) h -= 360.0;  // byte rounding of red may land a hair past 0 degrees
    EXPECT_LE(h, previous + 0.5) << "t = " << i / 100.0;
    previous = h;
  }
  EXPECT_LT(previous, 1.0);  // red at the top
}

}  // namespace
}  // namespace sculpt::test
