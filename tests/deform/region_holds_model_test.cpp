// A radius region one of whose balls holds the whole model runs as the global frame: the same
// points by the same bits, without the region's queries (the index's moved list, which only a
// region frame keeps, shows which path ran); so does one holding more than a sixth of the
// model (the cheaper frame, RegionSettings::global_when_cheaper), and one of less stays a
// region; just short of the whole model it is still a region when told to stay one; and the
// radius a budget asks for stops where its ball holds everything, so it can shrink back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sphere_settings.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

DeformSettings settings(double region_radius, bool global_when_cheaper = true) {
  DeformSettings s = frames::sphere_settings(0.08, 0.1, region_radius);
  s.region.global_when_cheaper = global_when_cheaper;
  return s;
}

using test::same_bytes;

// Three fingers sliding over a sphere centred away from the origin (the box, not the origin,
// decides), eight frames, each deforming the last one's output.
struct Stroke {
  PointModel model;
  std::size_t collisions = 0, region_points = 0, border_points = 0;
  bool list_kept = true;  // the index's moved list still complete after every frame
};

Stroke stroke(double region_radius, bool global_when_cheaper = true) {
  const Vec3 centre{40.0, -7.0, 3.0};
  Stroke out{make_sphere(3203, 1.0, centre)};
  Deformer deformer(out.model, settings(region_radius, global_when_cheaper));
  const Vec3 tops[3] = {normalized(Vec3{0.0, 0.0, 1.0}), normalized(Vec3{0.6, 0.0, 0.8}),
                        normalized(Vec3{0.0, 0.6, 0.8})};
  for (int frame = 0; frame < 8; ++frame) {
    ProbeMotion probes[3];
    for (int f = 0; f < 3; ++f) {
      const Vec3 slide{0.004 * frame, 0.002 * frame, 0.0};
      probes[f] = {centre + tops[f] * (1.06 - 0.01 * frame) + slide, centre + tops[f] * (0.96 - 0.01 * frame) + slide,
                   std::nullopt};
    }
    const FrameReport& r = deformer.deform(probes);
    out.collisions += r.collisions;
    out.region_points += r.region_points;
    out.border_points += r.border_points;
    out.list_kept = out.list_kept && deformer.index().moved_complete();
  }
  return out;
}

TEST(RegionHoldsModel, ABallHoldingTheModelMovesItAsTheGlobalFrameDoes) {
  const Stroke global = stroke(0.0);
  // The sphere's diameter is 2: a ball of 2.6 around a contact on it holds all of it, band and all.
  const Stroke held = stroke(2.6);
  ASSERT_GT(global.collisions, 8u);
  EXPECT_EQ(held.collisions, global.collisions);
  EXPECT_EQ(held.region_points, global.region_points);  // every point, every frame
  EXPECT_EQ(held.border_points, 0u);
  EXPECT_FALSE(held.list_kept);  // ran as a global frame, which overflows the moved list
  for (const auto member :
       {&PointModel::x, &PointModel::y, &PointModel::z, &PointModel::nx, &PointModel::ny, &PointModel::nz}) {
    EXPECT_TRUE(same_bytes(held.model.*member, global.model.*member));
  }
}

TEST(RegionHoldsModel, ABallJustShortOfTheModelIsStillARegionWhenToldToStayOne) {
  // From the top contact the far pole is 2 away: a ball of 1.9 leaves it out.
  const Stroke region = stroke(1.9, /*global_when_cheaper=*/false);
  ASSERT_GT(region.collisions, 8u);
  EXPECT_LT(region.region_points, region.collisions / 3 * 3203);
  EXPECT_GT(region.border_points, 0u);
  EXPECT_TRUE(region.list_kept);
}

TEST(RegionHoldsModel, ARegionOfMoreThanASixthOfTheModelMovesItAsTheGlobalFrameDoes) {
  const Stroke global = stroke(0.0);
  // Balls of 1.2 (a cap of 1.2 chord holds 36 % of the sphere) and of 1.9: both the global frame.
  for (const double radius : {1.2, 1.9}) {
    const Stroke cheaper = stroke(radius);
    EXPECT_EQ(cheaper.collisions, global.collisions);
    EXPECT_EQ(cheaper.region_points, global.region_points);
    EXPECT_EQ(cheaper.border_points, 0u);
    EXPECT_FALSE(cheaper.list_kept);
    for (const auto member :
         {&PointModel::x, &PointModel::y, &PointModel::z, &PointModel::nx, &PointModel::ny, &PointModel::nz}) {
      EXPECT_TRUE(same_bytes(cheaper.model.*member, global.model.*member)) << "radius " << radius;
    }
  }
  // Balls of 0.3 (caps of 2.3 % each, three fingers) stay a region, band and all.
  const Stroke region = stroke(0.3);
  ASSERT_GT(region.collisions, 8u);
  EXPECT_LT(6 * region.region_points, region.collisions / 3 * 3203);
  EXPECT_GT(region.border_points, 0u);
  EXPECT_TRUE(region.list_kept);
}

TEST(RegionHoldsModel, TheRadiusStopsWhereItsBallHoldsTheModelAndShrinksBack) {
  PointModel sphere = make_sphere();
  Deformer deformer(sphere, settings(0.5));
  // No point of the bounding box is farther from another than its diagonal; the band (the bc
  // radius, 0.08) on top.
  Vec3 lo = sphere.position(0), hi = lo;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    const Vec3 p = sphere.position(i);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double holds_all = deformer.set_region_radius(std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isfinite(holds_all));
  EXPECT_NEAR(holds_all, norm(hi - lo) + 0.08, 1e-6);
  EXPECT_EQ(deformer.set_region_radius(1e300), holds_all);
  EXPECT_EQ(deformer.set_region_radius(holds_all * 0.25), holds_all * 0.25);
  EXPECT_EQ(deformer.set_region_radius(std::nan("")), deformer.min_region_radius());
  // Moves widen the box the points can be in; an undo to the base narrows it back.
  const PointModel base = sphere;
  const ProbeMotion push{{0.0, 0.0, 1.1}, {0.0, 0.0, 0.9}, std::nullopt};
  ASSERT_EQ(deformer.deform({&push, 1}).collisions, 1u);
  EXPECT_GT(deformer.set_region_radius(std::numeric_limits<double>::infinity()), holds_all);
  deformer.restore(base);
  EXPECT_EQ(deformer.set_region_radius(std::numeric_limits<double>::infinity()), holds_all);
}

}  // namespace
}  // namespace sculpt::deform
