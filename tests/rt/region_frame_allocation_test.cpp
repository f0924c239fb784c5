// A five-finger region frame allocates nothing, from its very first frame: the region's radix
// sort, the blocked QR and the Jacobi SVD work in storage reserved at set-up or on the stack.
// (In tests/rt because the allocation counter's operators live in this binary.)
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "support/allocation_counter.hpp"

namespace sculpt {
namespace {

TEST(RegionFrameAllocation, FiveFingerRegionFramesAllocateNothingFromTheFirst) {
  deform::PointModel model = deform::make_sphere(40000);
  deform::DeformSettings settings;
  const double spacing = 0.01;  // about the 40,000-point sphere's nearest-neighbour distance
  settings.contact.bc_radius = spacing;
  settings.contact.min_source_distance = 0.25 * spacing;
  settings.contact.guard_distance = 1.5 * spacing;
  settings.region.kind = deform::RegionSettings::Kind::kRadius;
  settings.region.radius = 20.0 * spacing;
  deform::Deformer deformer(model, settings);
  std::vector<deform::ProbeMotion> probes;
  for (std::size_t f = 0; f < 5; ++f) {
    const std::size_t i = (f + 1) * model.size() / 6;
    const deform::Vec3 a = model.position(i), n = model.normal(i);
    probes.push_back({a + n * (2.0 * spacing), a - n * spacing, std::nullopt});
  }
  std::uint64_t allocations = 0;
  std::size_t collisions = 0, border = 0;
  {
    test::AllocationCounter counter;
    for (int frame = 0; frame < 3; ++frame) {
      const deform::FrameReport& r = deformer.deform(probes);
      collisions += r.collisions;
      border += r.border_points;
    }
    allocations = counter.count();
  }
  EXPECT_GT(collisions, 0u);
  EXPECT_GT(border, 100u);  // a real band, rows in several of the solve's blocks
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace sculpt
