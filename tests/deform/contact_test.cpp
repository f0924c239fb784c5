// Collision detection and force set-up (thesis 4.2.1, 4.3.1) on shapes whose inside is known.
#include "sculpt/deform/contact.hpp"

#include <gtest/gtest.h>

#include "sculpt/deform/generators.hpp"

namespace sculpt::deform {
namespace {

class SphereContact : public ::testing::Test {
 protected:
  PointModel sphere_ = make_sphere(3203, 1.0);
  PointIndex index_{sphere_};
  ContactSettings push_;
};

TEST_F(SphereContact, WithNormalsInsideIsNegativeOutsideIsPositive) {
  const SurfaceSide in = locate(sphere_, index_, 0.0, {0.0, 0.0, 0.9}, push_);
  const SurfaceSide out = locate(sphere_, index_, 0.0, {0.0, 0.0, 1.1}, push_);
  EXPECT_LT(in.side, 0.0);
  EXPECT_GT(out.side, 0.0);
  EXPECT_TRUE(crossed(ContactMode::kPush, in.side));
  EXPECT_FALSE(crossed(ContactMode::kPush, out.side));
  EXPECT_TRUE(crossed(ContactMode::kPull, out.side));
  EXPECT_FALSE(crossed(ContactMode::kPull, in.side));
  EXPECT_EQ(in.nearest, out.nearest);  // the same pole point, from either side
  EXPECT_NEAR(norm(sphere_.position(in.nearest)), 1.0, 1e-6);
}

// Without normals the thesis uses a point known to be outside; a reference far out along +z
// sees the top of the sphere the same way the normals do.
TEST_F(SphereContact, WithoutNormalsTheReferencePointDecides) {
  PointModel bare = sphere_;
  bare.clear_normals();
  ContactSettings settings;
  settings.reference = Vec3{0.0, 0.0, 10.0};
  const PointIndex index(bare);
  EXPECT_LT(locate(bare, index, 0.0, {0.02, 0.01, 0.93}, settings).side, 0.0);
  EXPECT_GT(locate(bare, index, 0.0, {0.02, 0.01, 1.07}, settings).side, 0.0);
}

TEST_F(SphereContact, GrazingAndFarAwayProbesDoNotCollide) {
  const std::uint32_t a = locate(sphere_, index_, 0.0, {0.0, 0.0, 1.0}, push_).nearest;
  const Vec3 pa = sphere_.position(a);
  const Vec3 n = sphere_.normal(a);
  // A probe sliding exactly in the tangent plane at A has n . (P - A) == 0: grazing by A's
  // plane; the surface through the points around it leaves that plane by a hair (0.2 % of the
  // step: the sampled sphere is not exactly tangent to it at A).
  const Vec3 tangent = normalized(cross(n, Vec3{1.0, 0.0, 0.0}));
  const double step = 1e-4;
  const SurfaceSide graze = locate(sphere_, index_, 0.0, pa + tangent * step, push_);
  EXPECT_EQ(graze.nearest, a);
  EXPECT_NEAR(graze.plane_side, 0.0, 1e-9);
  EXPECT_NEAR(graze.side, 0.0, 2e-3 * step);
  EXPECT_FALSE(crossed(ContactMode::kPush, 0.0));
  EXPECT_FALSE(crossed(ContactMode::kPull, 0.0));
  const SurfaceSide far = locate(sphere_, index_, 0.0, {5.0, -4.0, 3.0}, push_);
  EXPECT_GT(far.side, 0.0);
  EXPECT_GT(far.distance, 5.0);
}

TEST(ForceSetup, PreviousPositionIsTheSourceWhenFarEnough) {
  const ProbeMotion m{{0, 0, 1.2}, {0, 0, 0.95}, std::nullopt};
  const ForceSetup f = set_up_force(m, {0, 0, 1}, 0.01);
  EXPECT_EQ(f.rule, SourceRule::kPrevious);
  EXPECT_EQ(f.source, (Vec3{0, 0, 1.2}));
  EXPECT_NEAR(norm(f.force - Vec3{0, 0, -0.05}), 0.0, 1e-15);
}

// Δd: the previous position is too close to A, so the one before it becomes the source.
TEST(ForceSetup, EarlierPositionWhenThePreviousIsCloserThanDeltaD) {
  const ProbeMotion m{{0, 0, 1.005}, {0, 0, 0.95}, Vec3{0, 0, 1.3}};
  const ForceSetup f = set_up_force(m, {0, 0, 1}, 0.01);
  EXPECT_EQ(f.rule, SourceRule::kEarlier);
  EXPECT_EQ(f.source, (Vec3{0, 0, 1.3}));
}

TEST(ForceSetup, PushedBackAlongMinusFWhenNoPositionIsUsable) {
  const ProbeMotion m{{0, 0, 1.005}, {0, 0.03, 0.96}, Vec3{0, 0, 1.002}};
  const Vec3 a{0, 0, 1};
  const ForceSetup f = set_up_force(m, a, 0.01);
  EXPECT_EQ(f.rule, SourceRule::kPushedBack);
  EXPECT_NEAR(norm(f.source - a), 0.01, 1e-15);
  EXPECT_NEAR(dot(normalized(f.source - a), normalized(f.force)), -1.0, 1e-12);
}

TEST(ContactSettings, RejectsNonPositiveOffsets) {
  ContactSettings s;
  s.bc_radius = 0.0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = ContactSettings{};
  s.min_source_distance = -1.0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = ContactSettings{};
  s.guard_distance = -0.1;
  EXPECT_THROW(s.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
