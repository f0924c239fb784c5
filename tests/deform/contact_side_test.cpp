// The side of a probe as collision detection reads it (contact.hpp's locate): the surface of
// the points around the probe, anchored at the nearest point A, checked against surfaces whose
// exact signed distance is known.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"

namespace sculpt::deform {
namespace {

// On a flat patch whose normals are its plane's, every point's plane is the same plane, so the
// side is the exact distance to it, where the one-point test agrees too.
TEST(SurfaceSideTest, OnAFlatPatchItIsTheExactDistanceToThePlane) {
  const PointModel plane = make_plane_patch(41, 0.05);
  const PointIndex index(plane);
  ContactSettings settings;
  settings.bc_radius = 0.05;
  for (double x : {-0.3, -0.013, 0.0, 0.021, 0.2}) {
    for (double z : {-0.09, -0.01, -1e-4, 0.0, 3e-3, 0.07}) {
      const Vec3 probe{x, 0.37 * x + 0.004, z};
      const SurfaceSide s = locate(plane, index, 0.0, probe, settings);
      EXPECT_NEAR(s.side, z, 1e-9) << x << " " << z;
      EXPECT_NEAR(s.plane_side, z, 1e-9) << x << " " << z;
    }
  }
}

// At a model point the side is 0, as the thesis's grazing rule has it, even on a curved model
// where the neighbours' planes pass above the point: the surface goes through the samples.
TEST(SurfaceSideTest, AtAModelPointTheSideIsZero) {
  const PointModel sphere = make_sphere(3203, 1.0);
  const PointIndex index(sphere);
  ContactSettings settings;
  settings.bc_radius = 0.07;
  for (std::size_t i = 0; i < sphere.size(); i += 97) {
    const SurfaceSide s = locate(sphere, index, 0.0, sphere.position(i), settings);
    EXPECT_EQ(s.nearest, i);
    EXPECT_EQ(s.side, 0.0);
    EXPECT_EQ(s.plane_side, 0.0);
  }
  // Along the normal the side grows as the height does (the curvature of the neighbours'
  // planes cancels against A's own value).
  for (std::size_t i = 0; i < sphere.size(); i += 211) {
    const Vec3 a = sphere.position(i);
    for (double h : {-0.01, -1e-3, 1e-3, 0.01}) {
      const SurfaceSide s = locate(sphere, index, 0.0, a + sphere.normal(i) * h, settings);
      EXPECT_NEAR(s.side / h, 1.0, 0.05) << i << " " << h;
    }
  }
}

// A crease of the kind a finger makes while sliding: a floor (z = 0 for x <= 0) and a wall
// rising at 40 degrees ahead of it (z = x tan 40 for x > 0), sampled on a grid of spacing s,
// with each point's exact normal except along the crease line, where the carried normal has
// tilted 10 degrees forward (as it did in the sheet slide that `sculpt check` reported). The
// exact signed distance to the two half-planes is the truth. A's plane alone calls a finger
// just under the wall outside; the surface of the points around it must not.
class Crease : public ::testing::Test {
 protected:
  static constexpr double kS = 0.05;
  const double wall_ = 40.0 * M_PI / 180.0;
  PointModel model_;

  void SetUp() override {
    model_.resize(17 * 17, true, false);
    std::size_t k = 0;
    const double tilt = 10.0 * M_PI / 180.0;
    for (int j = -8; j <= 8; ++j) {
      for (int i = -8; i <= 8; ++i) {
        const double y = j * kS;
        Vec3 p{i * kS, y, 0.0};
        Vec3 n{0.0, 0.0, 1.0};
        if (i > 0) {
          // along the wall by arc length i s
          p = {i * kS * std::cos(wall_), y, i * kS * std::sin(wall_)};
          n = {-std::sin(wall_), 0.0, std::cos(wall_)};
        } else if (i == 0) {
          n = {std::sin(tilt), 0.0, std::cos(tilt)};
        }
        model_.set_position(k, p);
        model_.set_normal(k++, n);
      }
    }
  }

  // Exact signed distance to the floor and wall half-planes: the distance to the nearer one
  // (or to the crease line where a half-plane ends), negative below the surface.
  double truth(const Vec3& q) const {
    const double to_crease = std::hypot(q.x, q.z);
    const double floor = q.x <= 0.0 ? std::abs(q.z) : to_crease;
    const double along = q.x * std::cos(wall_) + q.z * std::sin(wall_);
    const double wall = along >= 0.0 ? std::abs(-std::sin(wall_) * q.x + std::cos(wall_) * q.z) : to_crease;
    const double height = q.x <= 0.0 ? 0.0 : q.x * std::tan(wall_);
    return (q.z < height ? -1.0 : 1.0) * std::min(floor, wall);
  }
};

TEST_F(Crease, AFingerUnderTheWallIsInsideThoughANearestNormalTiltedForward) {
  const PointIndex index(model_);
  ContactSettings settings;
  settings.bc_radius = kS;
  const Vec3 probe{0.3 * kS, 0.0, -0.05 * kS};
  const SurfaceSide s = locate(model_, index, 0.0, probe, settings);
  ASSERT_LT(truth(probe), -0.2 * kS);  // the wall is 0.23 s above it
  EXPECT_EQ(model_.position(s.nearest).x, 0.0);
  EXPECT_GT(s.plane_side, 0.0);  // A's plane alone: outside
  EXPECT_LT(s.side, 0.0);        // the surface of the points around it: inside
}

// Around the crease, wherever the probe is more than s/5 from the surface and within 2 s of
// it, the side has the truth's sign; A's plane alone gets some of them wrong (so this test
// tells the two apart).
TEST_F(Crease, TheSideHasTheExactSurfacesSignAroundTheCrease) {
  const PointIndex index(model_);
  ContactSettings settings;
  settings.bc_radius = kS;
  int judged = 0, wrong = 0, plane_wrong = 0;
  for (double x = -1.5 * kS; x <= 1.5 * kS; x += 0.1 * kS) {
    for (double z = -1.5 * kS; z <= 1.5 * kS; z += 0.1 * kS) {
      const Vec3 probe{x, 0.013, z};
      const double t = truth(probe);
      if (std::abs(t) < 0.2 * kS) continue;
      const SurfaceSide s = locate(model_, index, 0.0, probe, settings);
      ++judged;
      wrong += (s.side < 0.0) != (t < 0.0);
      plane_wrong += (s.plane_side < 0.0) != (t < 0.0);
    }
  }
  EXPECT_GT(judged, 200);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(plane_wrong, 0);
}

// The same crease under a deformer: a finger coming down from above the wall to just under it
// collides and pushes (A's plane alone called it free: the sheet slide's pass-through).
TEST_F(Crease, TheDeformerSeesAFingerUnderTheWallAndPushes) {
  DeformSettings settings;
  settings.contact.bc_radius = kS;
  settings.contact.min_source_distance = 0.25 * kS;
  settings.contact.guard_distance = 1.5 * kS;
  PointModel model = model_;
  Deformer deformer(model, settings);
  const ProbeMotion m{{0.3 * kS, 0.0, 0.6 * kS}, {0.3 * kS, 0.0, -0.05 * kS}, std::nullopt};
  ASSERT_GT(truth(m.previous), 0.0);
  ASSERT_LT(truth(m.current), -0.2 * kS);
  const FrameReport& r = deformer.deform({&m, 1});
  ASSERT_FALSE(deformer.frames().empty());
  EXPECT_EQ(deformer.frames().front().contacts[0].state, ProbeState::kCollided);
  EXPECT_GE(r.collisions, 1u);
  EXPECT_GT(r.max_displacement, 0.0);
}

// Without normals the outside of each point is the direction to the reference point, and the
// same surface is built from those.
TEST(SurfaceSideTest, WithAReferencePointTheSameRuleHolds) {
  PointModel plane = make_plane_patch(21, 0.05);
  plane.clear_normals();
  const PointIndex index(plane);
  ContactSettings settings;
  settings.bc_radius = 0.05;
  settings.reference = Vec3{0.0, 0.0, 1e3};  // far above: every direction is +z to 1e-6
  for (double z : {-0.04, -0.002, 0.002, 0.04}) {
    const SurfaceSide s = locate(plane, index, 0.0, {0.013, -0.02, z}, settings);
    EXPECT_NEAR(s.side, z, 1e-6 * 0.5);
  }
}

// On a dense model the smoothing length shrinks so that a query holds about as many points
// whatever eps is; on a sparse one it is eps.
TEST(SurfaceSideTest, SmoothingIsEpsOrShrunkOnADenseModel) {
  const PointModel plane = make_plane_patch(101, 0.01);
  const PointIndex index(plane);
  EXPECT_DOUBLE_EQ(side_smoothing(plane, index, 0.015), 0.015);  // 9 points in the ball
  const double wide = side_smoothing(plane, index, 0.2);         // about 1,250 points in the ball
  EXPECT_LT(wide, 0.04);
  EXPECT_GT(wide, 0.02);
}

}  // namespace
}  // namespace sculpt::deform
