#include "sculpt/deform/contact.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::deform {

void ContactSettings::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string("contact: ") + name + " must be a positive finite number, got " +
                                  base::number_text(v));
    }
  };
  positive(bc_radius, "bc radius (eps)");
  positive(min_source_distance, "minimum source distance (delta d)");
  if (!(guard_distance >= 0.0) || !std::isfinite(guard_distance)) {
    throw std::invalid_argument("contact: guard distance (delta r) must be >= 0, got " +
                                base::number_text(guard_distance));
  }
  if (max_patch_points < 1 || max_patch_points > kMaxPatchPointsLimit) {
    throw std::invalid_argument("contact: max patch points must be 1 to " + std::to_string(kMaxPatchPointsLimit) +
                                ", got " + std::to_string(max_patch_points));
  }
  if (reference && !is_finite(*reference)) {
    throw std::invalid_argument("contact: the reference point is not finite");
  }
}

SurfaceSide locate(const PointModel& model, const PointIndex& index, double drift, const Vec3& probe,
                   const ContactSettings& settings) {
  SurfaceSide s;
  const PointIndex::Nearest near = index.nearest(model, probe, drift);
  s.nearest = near.index;
  s.distance = near.distance;
  if (near.index == PointIndex::kNoPoint) return s;
  const Vec3 a = model.position(near.index);
  const Vec3 v = probe - a;
  // Thesis 4.2.1.1: with normals, the sign of n_A . v. 4.2.1.2: without, the sign of the angle
  // between v and the direction to a point known to be outside. Either way a length along a
  // unit direction, so that it compares with Δd wherever the reference point stands.
  s.side = model.has_normals() ? dot(model.normal(near.index), v) : dot(v, normalized(*settings.reference - a));
  return s;
}

ForceSetup set_up_force(const ProbeMotion& motion, const Vec3& contact, double min_source_distance) {
  ForceSetup setup;
  setup.force = motion.current - contact;
  if (norm(motion.previous - contact) >= min_source_distance) {
    setup.source = motion.previous;
    setup.rule = SourceRule::kPrevious;
  } else if (motion.earlier && norm(*motion.earlier - contact) >= min_source_distance) {
    setup.source = *motion.earlier;
    setup.rule = SourceRule::kEarlier;
  } else {
    Vec3 away = normalized(-setup.force);
    if (squared_norm(away) == 0.0) away = normalized(motion.previous - contact);
    if (squared_norm(away) == 0.0) away = Vec3{0.0, 0.0, 1.0};
    setup.source = contact + away * min_source_distance;
    setup.rule = SourceRule::kPushedBack;
  }
  return setup;
}

}  // namespace sculpt::deform
