// The log is the edit history, also when a guard split a step into substeps: base model plus
// the recorded frames equals the live result bit for bit, and a hostile logged force is
// refused without touching the model.
#include <gtest/gtest.h>

#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/rt/transfer.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::rt {
namespace {

using test::same_bytes;

deform::DeformSettings folding_settings() {
  deform::DeformSettings s;
  s.kernel = {deform::KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  s.contact.bc_radius = 0.063;
  s.contact.min_source_distance = 0.016;
  s.contact.guard_distance = 0.095;
  // Only Δd, as in the thesis: deep presses from a close source then fold and get split.
  s.guards.clearance_ratio = 0.0;
  s.guards.finger_radius_clearance = false;
  return s;
}

TEST(SplitStepTransfer, ReplayingTheSubstepsReproducesTheLiveModelBitForBit) {
  const deform::PointModel base = deform::make_sphere();
  deform::PointModel live = base;
  const deform::DeformSettings s = folding_settings();
  deform::Deformer d(live, s);
  std::vector<logging::CollisionRecord> log;
  std::int64_t frame_id = 0;
  std::size_t split_steps = 0;
  const deform::Vec3 n = base.normal(0), a = base.position(0);
  deform::Vec3 at = a + n * 0.02;
  for (int k = 1; k <= 6; ++k) {
    const deform::ProbeMotion m{at, a - n * (0.08 * k), std::nullopt};
    const deform::FrameReport& r = d.deform({&m, 1});
    if (d.frames().size() > 1) ++split_steps;
    for (const deform::FrameReport& f : d.frames()) append_frame_records(f, s, frame_id++, k, log);
    at = r.contacts[0].probe_after;
  }
  ASSERT_GT(split_steps, 0u) << "the case must exercise the split";
  deform::PointModel replayed = base;
  const TransferStats stats = transfer(replayed, log);
  EXPECT_EQ(stats.frames, static_cast<std::size_t>(frame_id));
  EXPECT_TRUE(same_bytes(replayed, live));
}

TEST(SplitStepTransfer, ALoggedForceOf1e300IsRefusedAndTheModelKeepsItsBytes) {
  deform::PointModel model = deform::make_sphere();
  const deform::PointModel before = model;
  logging::CollisionRecord r;
  r.source = {0.0, 0.0, 1.2};
  r.effective_force = {0.0, 0.0, -1e300};
  r.shear_modulus = 3e7;
  r.poisson_ratio = 0.45;
  r.frame_id = 0;
  r.frame_size = 1;
  FrameTransfer t(model);
  EXPECT_THROW(t.apply({&r, 1}), std::invalid_argument);
  EXPECT_TRUE(same_bytes(model, before));
}

}  // namespace
}  // namespace sculpt::rt
