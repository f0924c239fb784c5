#include "approximations.hpp"

#include <cstdio>

namespace sculpt::tools::report {
namespace {

std::string spacings(const char* what, double k) {
  char text[64];
  std::snprintf(text, sizeof text, "%s %g sp", what, k);
  return text;
}

}  // namespace

std::vector<Approximation> approximations(const deform::DeformSettings& session, double spacing, bool has_normals,
                                          double auto_radius) {
  deform::DeformSettings base = session;
  base.region = deform::RegionSettings{};
  base.region.border_weight = session.region.border_weight;
  base.region.global_when_cheaper = session.region.global_when_cheaper;
  base.field.precision = deform::Precision::kFloat;
  base.field.carry_normals = true;
  base.field.fast_inverse_sqrt = false;
  base.traction = false;  // haptics does not move the model; its time is not the frame's
  std::vector<Approximation> rows;
  rows.push_back({"float", "precision", base, false});
  Approximation dbl{"double loop", "precision", base, false};
  dbl.settings.field.precision = deform::Precision::kDouble;
  rows.push_back(dbl);
  // 1/r from the processor's estimate and one Newton step (FieldOptions::fast_inverse_sqrt).
  Approximation fast{"fast 1/r", "precision", base, false};
  fast.settings.field.fast_inverse_sqrt = true;
  rows.push_back(fast);
  for (double k : kRegionSpacings) {
    Approximation r{spacings("region", k), "region", base, false};
    r.settings.region.kind = deform::RegionSettings::Kind::kRadius;
    r.settings.region.radius = k * spacing;
    rows.push_back(r);
  }
  if (auto_radius > 0.0) {
    Approximation r{"region auto", "region", base, true};
    r.settings.region.kind = deform::RegionSettings::Kind::kRadius;
    r.settings.region.radius = auto_radius;
    rows.push_back(r);
  }
  if (session.kernel.kind == deform::KernelKind::kKelvin) {
    for (double k : {1.0, 2.0}) {
      Approximation r{spacings("regularized eps", k), "kernel", base, false};
      r.settings.kernel.kind = deform::KernelKind::kRegularized;
      r.settings.kernel.regularization = k * spacing;
      rows.push_back(r);
    }
  } else {
    Approximation r{"kelvin", "kernel", base, false};
    r.settings.kernel.kind = deform::KernelKind::kKelvin;
    r.settings.kernel.regularization = 0.0;
    rows.push_back(r);
  }
  // The subsampling of boundary rows: each finger's patch thinned evenly to a cap (the deformer
  // does so past contact.max_patch_points); rows only where the cap is below the session's.
  for (std::size_t cap : {std::size_t{4}, std::size_t{2}}) {
    if (cap >= session.contact.max_patch_points) continue;
    char name[48];
    std::snprintf(name, sizeof name, "patch cap %zu pts", cap);
    Approximation r{name, "boundary rows", base, false};
    r.settings.contact.max_patch_points = cap;
    rows.push_back(r);
  }
  if (has_normals) {
    // The bounded normal update (FieldOptions::normal_skip_bound) at two bounds: a kept normal is
    // within 1.0e-3 and 1.0e-2 rad of the carried one in each frame.
    for (double bound : {1e-3, 1e-2}) {
      char name[48];
      std::snprintf(name, sizeof name, "normals bounded %g", bound);
      Approximation r{name, "normals", base, false};
      r.settings.field.normal_skip_bound = bound;
      rows.push_back(r);
    }
    Approximation r{"normals off", "normals", base, false};
    r.settings.field.carry_normals = false;
    rows.push_back(r);
  }
  return rows;
}

}  // namespace sculpt::tools::report
