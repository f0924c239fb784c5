// The region's points and its pinned band against a brute-force pass over every point: the
// union of the contacts' balls, in ascending index order, each point once, and the band the
// points not deeper than the border width inside any ball.
#include "sculpt/deform/region.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// A region whose balls find more than 1/kRegionPointCost of the model is run as the global
// frame (RegionSettings::global_when_cheaper): every point, no band. Radii swept through that
// share, two fingers: each build is global exactly when the brute-force union is over it
// (whether the balls were queried or every point tested, a test that stops once past the share),
// and a region otherwise, the brute-force union and band; told to stay local, never global.
TEST(Region, MoreThanTheCheaperShareOfTheModelIsTheGlobalFrame) {
  const PointModel model = make_sphere(5000);
  const PointIndex index(model);
  const std::vector<Vec3> contacts{model.position(10), model.position(2600)};
  // The radius grows past the share and shrinks back below it: after a global build the scan
  // counts before it lists, and the first region after the global builds is listed in full.
  std::vector<double> radii;
  for (int k = 0; k <= 28; ++k) radii.push_back(0.1 + 0.05 * k);
  for (int k = 27; k >= 0; --k) radii.push_back(0.1 + 0.05 * k);
  int global = 0, local = 0, scanned_global = 0, scanned_region_after_global = 0;
  for (const bool cheaper : {true, false}) {
    RegionSettings settings;
    settings.kind = RegionSettings::Kind::kRadius;
    settings.radius = 0.1;
    settings.global_when_cheaper = cheaper;
    Region region(settings, model, index, 0.02);
    bool last_global = false;
    for (const double radius : radii) {
      region.set_radius(radius);
      region.build(model, index, 0.0, contacts);
      const Expected e = brute_force(model, contacts, radius, radius - region.border_width());
      const bool over = kRegionPointCost * e.points.size() > model.size();
      ASSERT_EQ(region.global(), cheaper && over) << "radius " << radius << ", " << e.points.size() << " points";
      if (region.global()) {
        ++global;
        scanned_global += region.scanned() ? 1 : 0;  // the scan stops once past the share
        EXPECT_TRUE(region.points().empty());
        EXPECT_TRUE(region.border().empty());
      } else {
        local += over ? 1 : 0;
        scanned_region_after_global += last_global && region.scanned() ? 1 : 0;
        EXPECT_EQ(std::vector<std::uint32_t>(region.points().begin(), region.points().end()), e.points);
        EXPECT_EQ(std::vector<std::uint32_t>(region.border().begin(), region.border().end()), e.border);
      }
      last_global = region.global();
    }
  }
  EXPECT_GT(global, 10);     // the sweep crossed the share both ways
  EXPECT_EQ(local, global);  // the same radii stayed regions when told to
  // A growing radius soon has every point tested; a region's first build queries its balls.
  EXPECT_GT(scanned_global, 0);
  EXPECT_EQ(scanned_region_after_global, 1);
  RegionSettings wide;
  wide.kind = RegionSettings::Kind::kRadius;
  wide.radius = 1.2;
  Region first(wide, model, index, 0.02);
  first.build(model, index, 0.0, contacts);
  ASSERT_GT(kRegionPointCost * brute_force(model, contacts, 1.2, 1.2 - first.border_width()).points.size(),
            model.size());
  EXPECT_TRUE(first.global());
  EXPECT_FALSE(first.scanned());
}

// Balls that hold a large share of the model are cheaper to collect by testing every point
// (Region::scan_pays, judged by what the last build found). A stroke that grows its radius
// until the builds scan and shrinks it until they query again, with points moved under a drift
// between builds: every build is the brute-force union and band of the points where they are
// now, whichever way it was collected, and both ways are met.
TEST(Region, BuildsThatScanEveryPointCollectWhatTheQueriesWould) {
  const PointModel original = make_sphere(5000);
  PointModel model = original;
  const PointIndex index(original);  // built before the moves: queries allow for the drift
  RegionSettings settings;
  settings.kind = RegionSettings::Kind::kRadius;
  settings.radius = 0.2;
  settings.global_when_cheaper = false;  // the collection itself, which a cheaper global frame skips
  Region region(settings, model, index, 0.02);
  const double drift = 0.01;
  int scanned = 0, queried = 0;
  for (int frame = 0; frame < 24; ++frame) {
    // The radius grows to 1.3 and back; three fingers slide along the sphere, two of them close.
    const double radius = 0.2 + 1.1 * std::sin(3.14159 * frame / 23.0);
    region.set_radius(radius);
    const double a = 0.05 * frame;
    const std::vector<Vec3> contacts = {{std::cos(a), std::sin(a), 0.0},
                                        {std::cos(a + 0.1), std::sin(a + 0.1), 0.05},
                                        {0.0, std::sin(a), -std::cos(a)}};
    // Points near the first finger sink by up to the drift from where the index has them, as
    // a press would leave them; the region is told how far any moved since its last build.
    double moved = 0.0;
    for (std::size_t i = 0; i < model.size(); ++i) {
      const Vec3 p = original.position(i);
      const Vec3 before = model.position(i);
      const double closeness = std::max(0.0, 1.0 - norm(p - contacts[0]) / 0.3);
      model.set_position(i, p * (1.0 - 0.9 * drift * closeness));
      ASSERT_LE(norm(model.position(i) - p), drift);
      moved = std::max(moved, norm(model.position(i) - before));
    }
    region.add_move(moved);
    region.build(model, index, drift, contacts);
    SCOPED_TRACE(::testing::Message() << "frame " << frame << ", radius " << radius);
    const Expected e = brute_force(model, contacts, radius, radius - region.border_width());
    if (region.global()) {
      EXPECT_EQ(e.points.size(), model.size());
      EXPECT_TRUE(e.border.empty());
      continue;
    }
    EXPECT_EQ(std::vector<std::uint32_t>(region.points().begin(), region.points().end()), e.points);
    EXPECT_EQ(std::vector<std::uint32_t>(region.border().begin(), region.border().end()), e.border);
    (region.scanned() ? scanned : queried) += 1;
  }
  EXPECT_GE(scanned, 3);
  EXPECT_GE(queried, 3);
  EXPECT_GT(region.balls().hits(), 0u);  // some queries came from balls kept across frames
}

// Moves the points between `from` and `to` of c (at their current positions) radially to
// `at` from c; returns how far the farthest moved.
double move_radially(PointModel& model, const Vec3& c, double from, double to, double at) {
  double farthest = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Vec3 p = model.position(i);
    const double d = norm(p - c);
    if (!(d > from && d < to)) continue;
    model.set_position(i, c + (p - c) * (at / d));
    farthest = std::max(farthest, norm(model.position(i) - p));
  }
  return farthest;
}

// A stroke keeps its balls' candidates across frames (BallCache): moves larger than the margin
// the balls were found with must reach them through add_move(), and a restore (back_to_base)
// or a write from outside (remeasure) must drop them, or points that came into a ball are
// missed. Each case moves points from beyond the kept ball into the region or back.
TEST(Region, KeptBallsFollowEveryMoveAndNoneSurvivesARestoreOrARemeasure) {
  const PointModel original = make_sphere(20000);
  PointModel model = original;
  const PointIndex index(original);  // queries allow for the drift since this snapshot
  RegionSettings settings;
  settings.kind = RegionSettings::Kind::kRadius;
  settings.radius = 0.3;
  Region region(settings, model, index, 0.02);
  const std::vector<Vec3> contacts = {model.position(100)};
  const double drift = 0.5;
  const auto matches = [&](const char* step) {
    region.build(model, index, drift, contacts);
    SCOPED_TRACE(step);
    const Expected e = brute_force(model, contacts, settings.radius, settings.radius - region.border_width());
    EXPECT_EQ(std::vector<std::uint32_t>(region.points().begin(), region.points().end()), e.points);
    EXPECT_EQ(std::vector<std::uint32_t>(region.border().begin(), region.border().end()), e.border);
  };
  // A finger held still until its ball is kept and used (a build after crowded points may
  // scan instead of querying, and a press queries plainly).
  const auto stroke = [&] {
    const std::size_t hits = region.balls().hits();
    for (int frame = 0; frame < 4 && region.balls().hits() == hits; ++frame) matches("held");
    ASSERT_GT(region.balls().hits(), hits);
  };
  const double kept = settings.radius * (1.0 + BallCache::kRegionMargin);
  // Told: points from beyond the kept ball carried into the region.
  stroke();
  region.add_move(move_radially(model, contacts[0], kept, kept + 0.1, 0.2));
  matches("after a move it was told of");
  // A write from outside, not told but remeasured.
  stroke();
  ASSERT_GT(move_radially(model, contacts[0], kept + 0.1, kept + 0.2, 0.25), 0.2);
  region.remeasure(model);
  matches("after a write from outside");
  // A restore to the base: points the stroke had pushed out come back in.
  model = original;
  region.back_to_base();
  region.add_move(move_radially(model, contacts[0], 0.05, 0.15, kept + 0.1));
  stroke();
  model = original;
  region.back_to_base();
  matches("after a restore");
}

}  // namespace
}  // namespace sculpt::deform
