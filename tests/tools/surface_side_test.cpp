// The sweep's inside-ness oracle against closed-form geometry: a point at a known depth inside
// a plane or a sphere must come out at that depth, on the inside, with the right normal.
#include <gtest/gtest.h>

#include <cmath>

#include "sculpt/deform/generators.hpp"
#include "surface_side.hpp"

namespace sculpt::tools::check {
namespace {

using deform::Vec3;

// A square grid on the plane through `origin` spanned by unit vectors u, v.
deform::PointModel tilted_plane(const Vec3& origin, const Vec3& u, const Vec3& v, int half, double spacing) {
  deform::PointModel m;
  for (int i = -half; i <= half; ++i) {
    for (int j = -half; j <= half; ++j) m.push_back(origin + u * (i * spacing) + v * (j * spacing));
  }
  return m;
}

TEST(SurfaceSideOracle, DepthBelowATiltedPlaneIsExact) {
  const Vec3 n = deform::normalized({1, 2, 3});
  const Vec3 u = deform::normalized(cross(n, {1, 0, 0}));
  const Vec3 v = cross(n, u);
  const Vec3 origin{0.4, -0.2, 1.0};
  const deform::PointModel plane = tilted_plane(origin, u, v, 10, 0.1);
  SurfaceSideOracle oracle;
  const Outside outside{Outside::Kind::kDirection, n * 5.0};  // any length: only the side counts
  for (double depth : {-0.037, -0.2, 0.0, 0.05}) {
    const Vec3 q = origin + u * 0.031 - v * 0.043 + n * depth;
    const PlaneSide s = oracle.side(plane, q, outside);
    EXPECT_NEAR(s.side, depth, 1e-6) << "depth " << depth;
    EXPECT_NEAR(dot(s.normal, n), 1.0, 1e-9);
  }
}

TEST(SurfaceSideOracle, DepthInsideASphereWithinItsCurvature) {
  const double radius = 2.0;
  const Vec3 centre{0.5, -1.0, 0.25};
  const deform::PointModel sphere = deform::make_sphere(20000, radius, centre);
  SurfaceSideOracle oracle;
  const Outside outside{Outside::Kind::kAwayFromCentroid, {}};
  // The nearest point is at most about half a spacing (0.05 here) beside the foot of the
  // query, so the plane through it is off the sphere by at most ~s^2 / (8 R) at the foot, plus
  // the PCA normal's tilt times the depth.
  const double tolerance = 1e-3;
  for (const Vec3& direction : {Vec3{0, 0, 1}, Vec3{0.3, -0.8, 0.2}, Vec3{-1, 1, -1}}) {
    const Vec3 w = deform::normalized(direction);
    for (double depth : {-0.1, -0.02, 0.03}) {
      const PlaneSide s = oracle.side(sphere, centre + w * (radius + depth), outside);
      EXPECT_NEAR(s.side, depth, tolerance) << "depth " << depth;
      EXPECT_GT(dot(s.normal, w), 0.99) << "the normal points out of the sphere";
    }
  }
}

TEST(SurfaceSideOracle, ARowOfPointsIsThePlaneThroughItFacingOutside) {
  deform::PointModel row;
  for (int i = -10; i <= 10; ++i) row.push_back({0.1 * i, 0.0, 0.0});
  SurfaceSideOracle oracle;
  const Outside up{Outside::Kind::kDirection, {0, 0, 1}};
  // Off the row sideways and below: the plane through the row normal to +z (the outside with
  // the row's direction removed) puts it at its height.
  EXPECT_NEAR(oracle.side(row, {0.01, 0.3, -0.02}, up).side, -0.02, 1e-9);
  const Outside tilted{Outside::Kind::kDirection, {1, 0, 1}};  // x is along the row: removed
  EXPECT_NEAR(oracle.side(row, {0.01, 0.3, 0.04}, tilted).side, 0.04, 1e-9);
}

TEST(SurfaceSideOracle, ASinglePointIsThePlaneNormalToTheOutside) {
  deform::PointModel one;
  one.push_back({1.0, 2.0, 3.0});
  one.push_back({1.0, 2.0, 3.0});  // coincident: still a single place
  SurfaceSideOracle oracle;
  const Outside out{Outside::Kind::kDirection, {0, 3, 4}};
  EXPECT_NEAR(oracle.side(one, {1.5, 2.0, 2.0}, out).side, -0.8, 1e-12);
}

}  // namespace
}  // namespace sculpt::tools::check
