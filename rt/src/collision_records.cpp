#include "sculpt/rt/collision_records.hpp"

#include <algorithm>
#include <cstdint>

#include "sculpt/rt/station.hpp"

namespace sculpt::rt {
namespace {

logging::Vec3d to_array(const deform::Vec3& v) { return {v.x, v.y, v.z}; }

logging::CollisionRecord contact_record(const deform::ContactReport& c, const FrameRecord& frame) noexcept {
  const deform::FrameReport& report = *frame.report;
  const deform::DeformSettings& settings = *frame.settings;
  // A radius region that ran as the global frame moved every point: recorded as what it did.
  const bool radius = settings.region.kind == deform::RegionSettings::Kind::kRadius && !report.global;
  const deform::Kernel& k = settings.kernel;
  logging::CollisionRecord r;
  r.tick = static_cast<std::int64_t>(frame.tick);
  r.time_s = frame.time_s;
  r.mode = settings.contact.mode == deform::ContactMode::kPull ? logging::CollisionMode::kPull
                                                               : logging::CollisionMode::kPush;
  r.probe = to_array(c.probe_after);
  r.contact_index = static_cast<std::int32_t>(c.nearest);
  r.contact = to_array(c.contact);
  r.source = to_array(c.source);
  r.force = to_array(c.force);
  r.weights = to_array(c.weights);
  r.effective_force = to_array(c.effective_force);
  r.bc_radius = settings.contact.bc_radius;
  r.region_kind = radius ? logging::RegionKind::kRadius : logging::RegionKind::kGlobal;
  r.region_centre = to_array(c.contact);
  r.region_radius = radius ? settings.region.radius : 0.0;
  r.kernel =
      k.kind == deform::KernelKind::kRegularized ? logging::KernelKind::kRegularized : logging::KernelKind::kKelvin;
  r.kernel_eps = k.regularization;
  r.shear_modulus = k.material.shear_modulus;
  r.poisson_ratio = k.material.poisson_ratio;
  r.form = settings.solver.form == deform::WeightForm::kForce ? logging::ForceForm::kForce : logging::ForceForm::kScale;
  r.residual = report.solve.relative_residual;  // the type and the docs say relative
  r.condition = report.solve.condition;
  r.frame_id = frame.frame_id;
  r.frame_size = static_cast<std::uint8_t>(report.collisions);
  r.min_jacobian = report.min_jacobian;
  r.miss = c.miss;
  std::size_t g = 0;
  deform::for_each_guard(report.guards, [&](const char*, std::uint32_t count) {
    if (g < r.guards.size()) r.guards[g++] = static_cast<std::int32_t>(std::min<std::uint32_t>(count, INT32_MAX));
  });
  return r;
}

}  // namespace

std::size_t frame_collision_records(const FrameRecord& frame, std::span<logging::CollisionRecord> out) noexcept {
  const deform::FrameReport& report = *frame.report;
  if (report.collisions == 0 || !report.solve.ok) return 0;
  // The report holds a slot per probe the deformer was sized for, not per probe of this frame:
  // slots past the frame's probes are left over from earlier frames and name no finger.
  const std::size_t probes =
      frame.probes.empty() ? report.contacts.size() : std::min(frame.probes.size(), report.contacts.size());
  const bool named = frame.fingers.size() >= probes;
  std::size_t written = 0;
  for (std::size_t k = 0; k < probes && written < out.size(); ++k) {
    const deform::ContactReport& c = report.contacts[k];
    if (c.state != deform::ProbeState::kCollided) continue;
    logging::CollisionRecord& r = out[written++];
    r = contact_record(c, frame);
    if (named) {
      r.hand = frame.fingers[k].hand;
      r.finger = frame.fingers[k].finger;
    }
  }
  return written;
}

}  // namespace sculpt::rt
