#pragma once
// A shared frame for the displacement loop's tests: five fingers pressing into the top of a
// 40,000-point sphere.

#include <vector>

#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/kernel.hpp"

namespace sculpt::deform::frames {

struct Frame {
  PointModel base;
  std::vector<SourceForce> sources;
};

// Five fingers 0.05 above the sphere's top, with forces that move the nearest points by a few
// hundredths (in units of 1 / alpha, so the material's G drops out).
inline Frame five_fingers() {
  Frame f{make_sphere(40000), {}};
  const double unit = 0.005 / coefficients(Kernel{}).alpha;
  for (int s = 0; s < 5; ++s) {
    const double a = 0.25 * (s - 2);
    f.sources.push_back({{a, 0.1 * s, 1.05}, Vec3{0.01 * s - 0.02, 0.01, -0.04} * unit});
  }
  return f;
}

}  // namespace sculpt::deform::frames
