#include "case_run.hpp"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cstdio>

namespace sculpt::tools::check {
namespace {

using deform::Vec3;

// The frames the invariants are checked in, relative to the case's own frame. The rotation is
// about no axis of the models and by no special angle, and the shift is a fair fraction of the
// model's size, so neither leaves a coordinate untouched.
constexpr double kGFactor = 1e4;
constexpr double kScaleFactor = 100.0;
constexpr double kUlps = 4.0;

Similarity rigid_for(const deform::PointModel& model) {
  const double d = model.bounding_box_diagonal();
  return Similarity::rigid({1.0, 2.0, 3.0}, 0.7, Vec3{0.3, -0.2, 0.1} * d);
}

std::string format(const char* what, double value, double limit) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %.3g > %.3g", what, value, limit);
  return text;
}

}  // namespace

CaseResult run_case(const CaseSpec& spec, const Tolerances& tol) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult result;
  result.spec = &spec;
  result.tolerance = spec.stroke ? tol.stroke : tol.single_frame;
  const Similarity frame = Similarity::scaling(spec.settings.scale);

  StrokeRunner base(*spec.model, spec.outside, spec.settings, frame, spec.mesh ? &spec.mesh->triangles : nullptr);
  spec.drive(base);
  result.metrics = base.metrics();
  const Metrics& m = result.metrics;
  if (m.non_finite) result.failures.push_back("non_finite " + std::to_string(m.non_finite));
  if (m.probe_inside) result.failures.push_back("probe_inside " + std::to_string(m.probe_inside));
  if (m.passed_through) result.failures.push_back("passed_through " + std::to_string(m.passed_through));
  if (spec.stroke && m.max_displacement_ratio > tol.max_displacement_ratio) {
    result.failures.push_back(format("max_displacement_ratio", m.max_displacement_ratio, tol.max_displacement_ratio));
  }

  if (spec.invariants) {
    const deform::PointModel initial = transformed(*spec.model, frame);
    auto compare = [&](const CaseSettings& settings, const Similarity& extra, std::optional<double>& out,
                       const char* what) {
      const Similarity variant_frame = extra.after(frame);
      // Only positions are compared here, so the variants go without the mesh oracle's time.
      StrokeRunner variant(*spec.model, spec.outside, settings, variant_frame);
      spec.drive(variant);
      const deform::PointModel variant_initial = transformed(*spec.model, variant_frame);
      // Positions are floats: kUlps float ulps of the largest coordinate (either frame) are
      // round-off whatever the physics, so a displacement that small is judged against them.
      const double magnitude =
          std::max(coordinate_magnitude(initial, Similarity{}), coordinate_magnitude(variant_initial, extra));
      const double floor = kUlps * FLT_EPSILON * magnitude / result.tolerance;
      out = relative_deviation(initial, base.model(), variant_initial, variant.model(), extra, floor);
      if (!(*out <= result.tolerance)) result.failures.push_back(format(what, *out, result.tolerance));
    };
    // G cancels in positions: compare with G 1e4 times larger, or smaller where that would pass
    // the largest modulus a material may have.
    CaseSettings stiffer = spec.settings;
    stiffer.shear_modulus *= stiffer.shear_modulus * kGFactor <= deform::kMaxShearModulus ? kGFactor : 1.0 / kGFactor;
    compare(stiffer, Similarity{}, result.g_deviation, "G invariance");
    compare(spec.settings, Similarity::scaling(kScaleFactor), result.scale_deviation, "scale invariance");
    // The chapter-4 form scales the components of F along the model's axes (MATH.md §3), so it is
    // not rotation-invariant by construction; it must still be invariant under a shift.
    Similarity motion = rigid_for(initial);
    if (spec.settings.form == deform::WeightForm::kScale) motion = Similarity::rigid({1, 0, 0}, 0.0, motion.shift);
    compare(spec.settings, motion, result.rigid_deviation, "rigid invariance");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace sculpt::tools::check
