#include "yardstick.hpp"

#include <cmath>
#include <numbers>

namespace sculpt::bench {

FloatPoints sphere_points(std::size_t n) {
  FloatPoints p;
  p.x.resize(n);
  p.y.resize(n);
  p.z.resize(n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double r = std::sqrt(1.0 - z * z), a = golden * static_cast<double>(i);
    p.x[i] = static_cast<float>(r * std::cos(a));
    p.y[i] = static_cast<float>(r * std::sin(a));
    p.z[i] = static_cast<float>(z);
  }
  return p;
}

FiveForces five_forces() {
  FiveForces f{};
  const double nu = 0.45, g = 3e7;
  const double c = 1.0 / (16.0 * std::numbers::pi * g * (1.0 - nu));
  for (int k = 0; k < FiveForces::kCount; ++k) {
    const double a = 1.2566 * k;  // around the equator, 1.2 out
    f.px[k] = static_cast<float>(1.2 * std::cos(a));
    f.py[k] = static_cast<float>(1.2 * std::sin(a));
    f.pz[k] = 0.1f * static_cast<float>(k);
    f.fx[k] = static_cast<float>(-1e3 * c * std::cos(a));
    f.fy[k] = static_cast<float>(-1e3 * c * std::sin(a));
    f.fz[k] = static_cast<float>(2e2 * c);
  }
  f.three_minus_four_nu = static_cast<float>(3.0 - 4.0 * nu);
  return f;
}

void bare_kelvin_pass(FloatPoints& points, const FiveForces& f) {
  float* __restrict x = points.x.data();
  float* __restrict y = points.y.data();
  float* __restrict z = points.z.data();
  const std::size_t n = points.size();
  const float k = f.three_minus_four_nu;
  // One read and one write per coordinate; the five sources stay in registers. The reciprocal
  // square root is the division-free form the compiler vectorises (-fno-math-errno).
#pragma GCC ivdep
  for (std::size_t i = 0; i < n; ++i) {
    const float qx = x[i], qy = y[i], qz = z[i];
    float ux = 0.0f, uy = 0.0f, uz = 0.0f;
    for (int s = 0; s < FiveForces::kCount; ++s) {
      const float rx = qx - f.px[s], ry = qy - f.py[s], rz = qz - f.pz[s];
      const float inv_r = 1.0f / std::sqrt(rx * rx + ry * ry + rz * rz);
      const float along = (rx * f.fx[s] + ry * f.fy[s] + rz * f.fz[s]) * inv_r * inv_r;
      ux += inv_r * (k * f.fx[s] + rx * along);
      uy += inv_r * (k * f.fy[s] + ry * along);
      uz += inv_r * (k * f.fz[s] + rz * along);
    }
    x[i] = qx + ux;
    y[i] = qy + uy;
    z[i] = qz + uz;
  }
}

void stream_pass(FloatPoints& points) {
  float* __restrict x = points.x.data();
  float* __restrict y = points.y.data();
  float* __restrict z = points.z.data();
  const std::size_t n = points.size();
  constexpr float kNearlyOne = 1.0000001f;
#pragma GCC ivdep
  for (std::size_t i = 0; i < n; ++i) {
    x[i] *= kNearlyOne;
    y[i] *= kNearlyOne;
    z[i] *= kNearlyOne;
  }
}

}  // namespace sculpt::bench
