// The region's points and its pinned band against a brute-force pass over every point: the
// union of the contacts' balls, in ascending index order, each point once, and the band the
// points not deeper than the border width inside any ball.
#include "sculpt/deform/region.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "sculpt/deform/generators.hpp"

namespace sculpt::deform {
namespace {

struct Expected {
  std::vector<std::uint32_t> points, border;
};

Expected brute_force(const PointModel& model, const std::vector<Vec3>& contacts, double radius, double inner) {
  Expected e;
  for (std::uint32_t i = 0; i < model.size(); ++i) {
    bool inside = false, deep = false;
    for (const Vec3& c : contacts) {
      const double d = norm(model.position(i) - c);
      inside = inside || d <= radius;
      deep = deep || d <= inner;
    }
    if (inside) e.points.push_back(i);
    if (inside && !deep) e.border.push_back(i);
  }
  return e;
}

TEST(Region, RadiusRegionIsTheUnionOfTheBallsInIndexOrder) {
  // 40,000 points: the region's set spans ten summary words (PointSet).
  const PointModel model = make_sphere(40000);
  const PointIndex index(model);
  RegionSettings settings;
  settings.kind = RegionSettings::Kind::kRadius;
  settings.radius = 0.3;
  const double bc_radius = 0.02;
  Region region(settings, model, index, bc_radius);
  // Two overlapping balls and one apart: overlapping points must appear once. Balls all apart
  // (no two centres within twice the radius) take the build's shortcut: the band decided ball
  // by ball; the last frame is apart by a hair more than that.
  const Vec3 near_pole = model.position(100);
  const Vec3 just_apart = near_pole + normalized(Vec3{1, 1, 0}) * (2.0 * settings.radius * (1.0 + 1e-6));
  const std::vector<std::vector<Vec3>> frames = {
      {model.position(100)},
      {model.position(100), model.position(20000), model.position(20050), model.position(39000)},
      {model.position(7)},
      {model.position(100), model.position(20000), model.position(39000)},
      {near_pole, just_apart},
  };
  ASSERT_GT(norm(model.position(100) - model.position(20000)), 2.0 * settings.radius);
  ASSERT_GT(norm(model.position(20000) - model.position(39000)), 2.0 * settings.radius);
  for (const std::vector<Vec3>& contacts : frames) {
    region.build(model, index, 0.0, contacts);
    const Expected e = brute_force(model, contacts, settings.radius, settings.radius - region.border_width());
    ASSERT_FALSE(e.points.empty());
    EXPECT_EQ(std::vector<std::uint32_t>(region.points().begin(), region.points().end()), e.points);
    EXPECT_EQ(std::vector<std::uint32_t>(region.border().begin(), region.border().end()), e.border);
    // The order the index is told of them in: the same set, repeats allowed.
    std::vector<std::uint32_t> as_found(region.points_as_found().begin(), region.points_as_found().end());
    std::sort(as_found.begin(), as_found.end());
    as_found.erase(std::unique(as_found.begin(), as_found.end()), as_found.end());
    EXPECT_EQ(as_found, e.points);
  }
  // Balls that each hold most of the sphere repeat most points: past the reserve (one model's
  // worth) the found order is dropped and the ascending points stand in for it. Together they
  // hold every point deep inside, so the frame is a global one after all.
  const std::vector<Vec3> pole_and_equator{model.position(100), model.position(20000)};
  region.set_radius(1.9);
  region.build(model, index, 0.0, pole_and_equator);
  ASSERT_EQ(region.points().size(), model.size());
  EXPECT_EQ(region.points_as_found().data(), region.points().data());
  EXPECT_EQ(region.points_as_found().size(), model.size());
  EXPECT_TRUE(region.border().empty());
  EXPECT_TRUE(region.global());
  // One ball, less its band, holds the sphere's bounding box: global, nothing collected.
  region.set_radius(3.0);
  region.build(model, index, 0.0, pole_and_equator);
  EXPECT_TRUE(region.global());
  EXPECT_TRUE(region.points().empty());
  // And back: a region again.
  region.set_radius(0.3);
  region.build(model, index, 0.0, pole_and_equator);
  EXPECT_FALSE(region.global());
  EXPECT_EQ(std::vector<std::uint32_t>(region.points().begin(), region.points().end()),
            brute_force(model, pole_and_equator, 0.3, 0.3 - region.border_width()).points);
}

}  // namespace
}  // namespace sculpt::deform
