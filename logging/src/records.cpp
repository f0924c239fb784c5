#include "sculpt/logging/records.hpp"

#include <cmath>
#include <cstddef>
#include <ctime>

namespace sculpt::logging {
namespace {

template <typename T>
void copy3(const std::array<T, 3>& from, T (&to)[3]) noexcept {
  for (std::size_t c = 0; c < 3; ++c) to[c] = from[c];
}

template <typename T>
void copy3(const T (&from)[3], std::array<T, 3>& to) noexcept {
  for (std::size_t c = 0; c < 3; ++c) to[c] = from[c];
}

bool finite3(const double (&v)[3]) noexcept {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

void to_lcm(const FingertipRecord& record, sculpt_lcm::fingertip_state_t& out) noexcept {
  out.utime = record.utime;
  out.tick = record.tick;
  out.hand = static_cast<std::int8_t>(record.hand);
  out.finger = static_cast<std::int8_t>(record.finger);
  copy3(record.raw, out.raw);
  copy3(record.filtered, out.filtered);
  copy3(record.registered, out.registered);
  out.accepted = record.accepted ? 1 : 0;
  out.in_contact = record.in_contact ? 1 : 0;
}

void to_lcm(const CollisionRecord& record, sculpt_lcm::collision_event_t& out) noexcept {
  out.utime = record.utime;
  out.tick = record.tick;
  out.time_s = record.time_s;
  out.hand = static_cast<std::int8_t>(record.hand);
  out.finger = static_cast<std::int8_t>(record.finger);
  out.mode = static_cast<std::int8_t>(record.mode);
  copy3(record.probe, out.probe);
  out.contact_index = record.contact_index;
  copy3(record.contact, out.contact);
  copy3(record.source, out.source);
  copy3(record.force, out.force);
  copy3(record.weights, out.weights);
  copy3(record.effective_force, out.effective_force);
  out.bc_radius = record.bc_radius;
  out.region_kind = static_cast<std::int8_t>(record.region_kind);
  copy3(record.region_centre, out.region_centre);
  out.region_radius = record.region_radius;
  out.region_id = record.region_id;
  out.kernel = static_cast<std::int8_t>(record.kernel);
  out.kernel_eps = record.kernel_eps;
  out.shear_modulus = record.shear_modulus;
  out.poisson_ratio = record.poisson_ratio;
  out.form = static_cast<std::int8_t>(record.form);
  out.residual = record.residual;
  out.condition = record.condition;
  out.frame_id = record.frame_id;
  out.frame_size = static_cast<std::int8_t>(record.frame_size);
  out.min_jacobian = record.min_jacobian;
  out.miss = record.miss;
  for (std::size_t g = 0; g < record.guards.size(); ++g) out.guards[g] = record.guards[g];
}

void to_lcm(const TickRecord& record, sculpt_lcm::tick_stats_t& out) noexcept {
  out.utime = record.utime;
  out.tick = record.tick;
  out.tick_time_us = record.tick_time_us;
  out.budget_us = record.budget_us;
  out.overruns = record.overruns;
  out.missed_periods = record.missed_periods;
  out.region_points = record.region_points;
  out.collisions = record.collisions;
  out.glove_state = record.glove_state;
  out.glove_age_ms = record.glove_age_ms;
  out.min_jacobian = record.min_jacobian;
  out.guards_acted = record.guards_acted;
  out.out_of_range = record.out_of_range;
}

bool from_lcm(const sculpt_lcm::collision_event_t& m, CollisionRecord& out) noexcept {
  using Event = sculpt_lcm::collision_event_t;
  if (m.hand < 0 || m.hand > 1 || m.finger < 0 || m.finger > 4) return false;
  if (m.mode != Event::MODE_PUSH && m.mode != Event::MODE_PULL) return false;
  if (m.region_kind < Event::REGION_GLOBAL || m.region_kind > Event::REGION_INDEX_SET) return false;
  if (m.kernel != Event::KERNEL_KELVIN && m.kernel != Event::KERNEL_REGULARIZED) return false;
  if (m.form != Event::FORM_SCALE && m.form != Event::FORM_FORCE) return false;
  if (m.frame_size < 1 || m.contact_index < 0) return false;
  if (!finite3(m.probe) || !finite3(m.contact) || !finite3(m.source) || !finite3(m.force) || !finite3(m.weights) ||
      !finite3(m.effective_force) || !finite3(m.region_centre)) {
    return false;
  }
  // Replay re-applies the kernel with these: a NaN material would spread NaN over the model.
  if (!std::isfinite(m.time_s) || !std::isfinite(m.bc_radius) || !std::isfinite(m.region_radius) ||
      !std::isfinite(m.kernel_eps) || !std::isfinite(m.shear_modulus) || !std::isfinite(m.poisson_ratio)) {
    return false;
  }
  out.utime = m.utime;
  out.tick = m.tick;
  out.time_s = m.time_s;
  out.hand = static_cast<std::uint8_t>(m.hand);
  out.finger = static_cast<std::uint8_t>(m.finger);
  out.mode = static_cast<CollisionMode>(m.mode);
  copy3(m.probe, out.probe);
  out.contact_index = m.contact_index;
  copy3(m.contact, out.contact);
  copy3(m.source, out.source);
  copy3(m.force, out.force);
  copy3(m.weights, out.weights);
  copy3(m.effective_force, out.effective_force);
  out.bc_radius = m.bc_radius;
  out.region_kind = static_cast<RegionKind>(m.region_kind);
  copy3(m.region_centre, out.region_centre);
  out.region_radius = m.region_radius;
  out.region_id = m.region_id;
  out.kernel = static_cast<KernelKind>(m.kernel);
  out.kernel_eps = m.kernel_eps;
  out.shear_modulus = m.shear_modulus;
  out.poisson_ratio = m.poisson_ratio;
  out.form = static_cast<ForceForm>(m.form);
  out.residual = m.residual;
  out.condition = m.condition;
  out.frame_id = m.frame_id;
  out.frame_size = static_cast<std::uint8_t>(m.frame_size);
  out.min_jacobian = m.min_jacobian;
  out.miss = m.miss;
  for (std::size_t g = 0; g < out.guards.size(); ++g) out.guards[g] = m.guards[g];
  return true;
}

}  // namespace sculpt::logging
