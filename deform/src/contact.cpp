#include "sculpt/deform/contact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"
#include "sculpt/deform/model_scale.hpp"

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

namespace {

// The outside direction at one model point: its normal, or towards the reference point.
Vec3 outside_at(const PointModel& model, std::uint32_t i, const ContactSettings& settings) noexcept {
  return model.has_normals() ? model.normal(i) : normalized(*settings.reference - model.position(i));
}

// An h-ball holding about this many points gives a smooth surface; more only costs time.
constexpr double kSideNeighbours = 24.0;

}  // namespace

double side_smoothing(const PointModel& model, const PointIndex& index, double bc_radius) {
  const double count = static_cast<double>(median_ball_count(model, index, bc_radius));
  // A surface's count grows with the radius squared.
  return count > kSideNeighbours ? bc_radius * std::sqrt(kSideNeighbours / count) : bc_radius;
}

SurfaceSide locate(const PointModel& model, const PointIndex& index, double drift, const Vec3& probe,
                   const ContactSettings& settings, double smoothing, std::vector<std::uint32_t>& neighbours,
                   std::uint32_t hint, BallCache* balls) noexcept {
  SurfaceSide s;
  const PointIndex::Nearest near =
      balls != nullptr ? balls->nearest(model, index, drift, probe, hint) : index.nearest(model, probe, drift, hint);
  s.nearest = near.index;
  s.distance = near.distance;
  if (near.index == PointIndex::kNoPoint) return s;
  const Vec3 a = model.position(near.index);
  // Thesis 4.2.1.1: with normals, the sign of n_A . v. 4.2.1.2: without, the sign of the angle
  // between v and the direction to a point known to be outside. Either way a length along a
  // unit direction, so that it compares with Δd wherever the reference point stands.
  s.plane_side = dot(outside_at(model, near.index, settings), probe - a);
  s.surface_side = s.plane_side;
  s.side = s.plane_side;
  const double h = smoothing;
  if (!(h > 0.0) || !(near.distance <= 2.0 * h)) return s;
  // Every point that weighs at the probe (|P - p|^2 < d^2 + 4h^2) or at A (|A - p| < 2h) lies
  // within d + 2h of the probe.
  const double reach = near.distance + 2.0 * h;
  if (!(balls != nullptr ? balls->within_radius(model, index, drift, probe, reach, neighbours)
                         : index.within_radius(model, probe, reach, neighbours, drift))) {
    return s;
  }
  const double inv = 1.0 / (4.0 * h * h);
  const double d2 = near.distance * near.distance;
  double weight_p = 0.0, sum_p = 0.0, weight_a = 0.0, sum_a = 0.0;
  for (const std::uint32_t j : neighbours) {
    const Vec3 p = model.position(j);
    const Vec3 o = outside_at(model, j, settings);
    const double tp = std::max(0.0, (squared_norm(probe - p) - d2) * inv);
    if (tp < 1.0) {
      const double w = (1.0 - tp) * (1.0 - tp);
      weight_p += w;
      sum_p += w * dot(o, probe - p);
    }
    const double ta = squared_norm(a - p) * inv;
    if (ta < 1.0) {
      const double w = (1.0 - ta) * (1.0 - ta);
      weight_a += w;
      sum_a += w * dot(o, a - p);
    }
  }
  // A itself weighs 1 in both sums, so neither is empty.
  if (!(weight_p > 0.0 && weight_a > 0.0)) return s;
  s.surface_side = sum_p / weight_p - sum_a / weight_a;
  // Across when either says so: inside for a push, outside for a pull.
  s.side = settings.mode == ContactMode::kPush ? std::min(s.plane_side, s.surface_side)
                                               : std::max(s.plane_side, s.surface_side);
  return s;
}

SurfaceSide locate(const PointModel& model, const PointIndex& index, double drift, const Vec3& probe,
                   const ContactSettings& settings) {
  std::vector<std::uint32_t> neighbours;
  neighbours.reserve(model.size());
  return locate(model, index, drift, probe, settings, side_smoothing(model, index, settings.bc_radius), neighbours);
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
