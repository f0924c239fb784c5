#pragma once
// Deform settings for frames on a unit sphere in the tests: the thesis's material, a contact
// of bc radius `bc_radius`, a guard distance, and a radius region when `region_radius` > 0.

#include "sculpt/deform/deformer.hpp"

namespace sculpt::deform::frames {

inline DeformSettings sphere_settings(double bc_radius, double guard_distance, double region_radius = 0.0) {
  DeformSettings s;
  s.kernel = {KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  s.contact.bc_radius = bc_radius;
  s.contact.min_source_distance = 0.01;
  s.contact.guard_distance = guard_distance;
  if (region_radius > 0.0) {
    s.region.kind = RegionSettings::Kind::kRadius;
    s.region.radius = region_radius;
  }
  return s;
}

}  // namespace sculpt::deform::frames
