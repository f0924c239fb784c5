// deform.max_patch_points: a finger's patch larger than the cap is thinned evenly, the frame
// still does what the full patch does (the contact follows the finger; the felt resultant is
// the same force, scaled for the points left out), and a cap that does not bind changes nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"

namespace sculpt::deform {
namespace {

DeformSettings wide_patch(std::size_t cap) {
  DeformSettings s;
  s.kernel = {KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  s.contact.bc_radius = 0.3;  // about 70 points of the 3,203-point unit sphere
  s.contact.min_source_distance = 0.01;
  s.contact.guard_distance = 0.1;
  s.contact.max_patch_points = cap;
  s.traction = true;
  return s;
}

struct Press {
  FrameReport report;
  Vec3 contact_moved;
};

Press press(std::size_t cap) {
  PointModel sphere = make_sphere();
  const PointModel before = sphere;
  Deformer deformer(sphere, wide_patch(cap));
  const ProbeMotion push{{0.0, 0.0, 1.1}, {0.0, 0.0, 0.93}, std::nullopt};
  Press p{deformer.deform({&push, 1}), {}};
  const std::uint32_t a = p.report.contacts[0].nearest;
  p.contact_moved = sphere.position(a) - before.position(a);
  return p;
}

TEST(PatchCap, AThinnedPatchPressesAndIsFeltLikeTheFullOne) {
  const Press full = press(kMaxPatchPointsLimit);
  const Press thinned = press(16);
  ASSERT_EQ(full.report.collisions, 1u);
  ASSERT_EQ(thinned.report.collisions, 1u);
  const ContactReport& f = full.report.contacts[0];
  const ContactReport& t = thinned.report.contacts[0];
  ASSERT_GT(f.boundary_points, 40u) << "the test needs a patch well above the cap";
  EXPECT_EQ(full.report.patches_thinned, 0u);
  EXPECT_EQ(thinned.report.patches_thinned, 1u);
  EXPECT_EQ(t.boundary_points, 16u);
  EXPECT_EQ(thinned.report.displacement_conditions, 16u);
  // The same press: the contact moves by nearly the same vector...
  EXPECT_LT(norm(thinned.contact_moved - full.contact_moved), 0.1 * norm(full.contact_moved));
  // ...and the finger feels nearly the same resultant (16 points standing for ~70).
  ASSERT_TRUE(f.has_traction);
  ASSERT_TRUE(t.has_traction);
  EXPECT_LT(norm(t.traction_resultant - f.traction_resultant), 0.2 * norm(f.traction_resultant))
      << "full " << f.traction_resultant.z << ", thinned " << t.traction_resultant.z;
}

TEST(PatchCap, ACapThatDoesNotBindChangesNothing) {
  const Press full = press(kMaxPatchPointsLimit);
  const Press loose = press(1024);
  EXPECT_EQ(loose.report.patches_thinned, 0u);
  EXPECT_EQ(loose.report.contacts[0].boundary_points, full.report.contacts[0].boundary_points);
  EXPECT_EQ(loose.contact_moved, full.contact_moved);
  EXPECT_EQ(loose.report.contacts[0].traction_resultant, full.report.contacts[0].traction_resultant);
}

TEST(PatchCap, OutOfRangeCapsAreRefusedAtSetUp) {
  PointModel sphere = make_sphere(200);
  EXPECT_THROW(Deformer(sphere, wide_patch(0)), std::invalid_argument);
  EXPECT_THROW(Deformer(sphere, wide_patch(kMaxPatchPointsLimit + 1)), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
