#pragma once
// The approximations a session could run with, each as the deformer settings that select it.
// Every one is measured against the same exact computation.

#include <string>
#include <vector>

#include "sculpt/deform/deformer.hpp"

namespace sculpt::tools::report {

struct Approximation {
  std::string name;
  std::string group;
  deform::DeformSettings settings;
  /// Each step uses the region radius the recorded session had in force (its auto region).
  bool recorded_radius = false;
};

/// The per-frame rows, from the session's settings: float against double (the float row is the
/// session's kernel, global region, normals carried: every other row differs from it in one
/// setting); the region at 5, 10, 20 and 40 spacings, and `auto` (the radii the session's budget
/// chose, when `auto_radius` > 0: its first); the regularized kernel at 1 and 2
/// spacings (Kelvin instead when the session is regularized); each finger's boundary rows
/// thinned to 4 and 2 points (a fingertip patch holds a few points at the default eps); the
/// bounded normal update at 1e-3 and 1e-2, and the normal update off (when the model has normals).
std::vector<Approximation> approximations(const deform::DeformSettings& session, double spacing, bool has_normals,
                                          double auto_radius);

/// The region radii of the region rows, in spacings.
inline constexpr double kRegionSpacings[] = {5.0, 10.0, 20.0, 40.0};

}  // namespace sculpt::tools::report
