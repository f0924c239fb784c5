#include "sculpt/deform/kernel.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sculpt::deform {

namespace {

// Streams print %g-style: a tiny value stays readable, where std::to_string would print 0.000000.
[[noreturn]] void refuse(const char* what, double value) {
  std::ostringstream text;
  text << what << ", got " << value;
  throw std::invalid_argument(text.str());
}

}  // namespace

void Material::validate() const {
  if (!(shear_modulus >= kMinShearModulus && shear_modulus <= kMaxShearModulus)) {
    refuse("material: shear modulus G must lie in [1e-15, 1e15]", shear_modulus);
  }
  if (!(poisson_ratio > -1.0 && poisson_ratio <= 0.5)) {
    refuse("material: Poisson's ratio nu must lie in (-1, 0.5]", poisson_ratio);
  }
}

void Kernel::validate() const {
  material.validate();
  if (kind == KernelKind::kRegularized && !(regularization > 0.0 && std::isfinite(regularization))) {
    refuse("kernel: the regularized Kelvinlet needs a positive finite radius eps", regularization);
  }
}

KernelCoefficients coefficients(const Kernel& kernel) {
  const double g = kernel.material.shear_modulus;
  const double nu = kernel.material.poisson_ratio;
  KernelCoefficients k;
  if (kernel.kind == KernelKind::kKelvin) {
    // U = c / R [ (3 - 4 nu) I + rh rh^T ],  c = 1 / (16 pi G (1 - nu))
    const double c = 1.0 / (16.0 * std::numbers::pi * g * (1.0 - nu));
    k.alpha = c * (3.0 - 4.0 * nu);
    k.gamma = c;
    // div u = -2 (1 - 2 nu) c (r.f) / R^3 and lambda (1 - 2 nu) = 2 G nu.
    k.lambda_div3 = -4.0 * g * nu * c;
  } else {
    // u = [ (a - b) / re + a eps^2 / (2 re^3) ] f + b / re^3 r (r.f),  a = 1/(4 pi G), b = a/(4(1-nu))
    const double a = 1.0 / (4.0 * std::numbers::pi * g);
    const double b = a / (4.0 * (1.0 - nu));
    const double eps2 = kernel.regularization * kernel.regularization;
    k.alpha = a - b;
    k.beta = a * eps2 / 2.0;
    k.gamma = b;
    k.eps_squared = eps2;
    // div u = (r.f) [ (2b - a) / re^3 + 3 eps^2 (b - a/2) / re^5 ], both terms carry (1 - 2 nu):
    // 2b - a = -a (1 - 2 nu) / (2 (1 - nu)),  b - a/2 = -a (1 - 2 nu) / (4 (1 - nu)).
    k.lambda_div3 = -g * nu * a / (1.0 - nu);
    k.lambda_div5 = -3.0 * eps2 * g * nu * a / (2.0 * (1.0 - nu));
  }
  return k;
}

namespace {

struct Separation {
  Vec3 r;
  double inv;   // 1 / r_eps
  double inv3;  // 1 / r_eps^3
  double inv5;  // 1 / r_eps^5
};

Separation separation(const KernelCoefficients& k, const Vec3& source, const Vec3& point) {
  Separation s;
  s.r = point - source;
  const double r2 = squared_norm(s.r) + k.eps_squared;
  s.inv = 1.0 / std::sqrt(r2);
  s.inv3 = s.inv / r2;
  s.inv5 = s.inv3 / r2;
  return s;
}

}  // namespace

Mat3 displacement_matrix(const Kernel& kernel, const Vec3& source, const Vec3& point) {
  return displacement_matrix(coefficients(kernel), source, point);
}

Mat3 displacement_matrix(const KernelCoefficients& k, const Vec3& source, const Vec3& point) {
  const Separation s = separation(k, source, point);
  const double diag = k.alpha * s.inv + k.beta * s.inv3;
  Mat3 u;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      u(a, b) = (a == b ? diag : 0.0) + k.gamma * s.inv3 * s.r[a] * s.r[b];
    }
  }
  return u;
}

Vec3 displacement(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point) {
  const KernelCoefficients k = coefficients(kernel);
  const Separation s = separation(k, source, point);
  const double rf = dot(s.r, force);
  return force * (k.alpha * s.inv + k.beta * s.inv3) + s.r * (k.gamma * s.inv3 * rf);
}

Mat3 displacement_gradient(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point) {
  // u = g(r) f + h(r) (r.f) r with g = alpha/r + beta/r^3, h = gamma/r^3, dr/dQ_m = r_m / r:
  // du_l/dQ_m = (g'/r) f_l r_m + (h'/r) (r.f) r_l r_m + h ((r.f) delta_lm + r_l f_m)
  const KernelCoefficients k = coefficients(kernel);
  const Separation s = separation(k, source, point);
  const double rf = dot(s.r, force);
  const double g_prime_over_r = -k.alpha * s.inv3 - 3.0 * k.beta * s.inv5;
  const double h_prime_over_r = -3.0 * k.gamma * s.inv5;
  const double h = k.gamma * s.inv3;
  Mat3 grad;
  for (int l = 0; l < 3; ++l) {
    for (int m = 0; m < 3; ++m) {
      grad(l, m) = g_prime_over_r * force[l] * s.r[m] + h_prime_over_r * rf * s.r[l] * s.r[m] +
                   h * ((l == m ? rf : 0.0) + s.r[l] * force[m]);
    }
  }
  return grad;
}

Vec3 stress_traction(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point,
                     const Vec3& normal) {
  const KernelCoefficients k = coefficients(kernel);
  const Separation s = separation(k, source, point);
  const double lambda_div = dot(s.r, force) * (k.lambda_div3 * s.inv3 + k.lambda_div5 * s.inv5);
  const Mat3 grad = displacement_gradient(kernel, source, force, point);
  const double g = kernel.material.shear_modulus;
  Vec3 t = normal * lambda_div;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) t[i] += g * (grad(i, j) + grad(j, i)) * normal[j];
  }
  return t;
}

Mat3 kelvin_traction_matrix(double nu, const Vec3& source, const Vec3& point, const Vec3& normal) {
  const Vec3 r = point - source;
  const double r2 = squared_norm(r);
  const Vec3 rh = r * (1.0 / std::sqrt(r2));
  const double cos_theta = dot(rh, normal);
  const double k = -1.0 / (8.0 * std::numbers::pi * (1.0 - nu) * r2);
  const double a = 1.0 - 2.0 * nu;
  Mat3 t;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      t(i, j) =
          k * (((i == j ? a : 0.0) + 3.0 * rh[i] * rh[j]) * cos_theta - a * (rh[i] * normal[j] - rh[j] * normal[i]));
    }
  }
  return t;
}

Vec3 kelvin_traction(double nu, const Vec3& source, const Vec3& force, const Vec3& point, const Vec3& normal) {
  const Mat3 t = kelvin_traction_matrix(nu, source, point, normal);
  Vec3 out;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) out[j] += force[i] * t(i, j);
  }
  return out;
}

Vec3 traction(const Kernel& kernel, const Vec3& source, const Vec3& force, const Vec3& point, const Vec3& normal) {
  if (kernel.kind == KernelKind::kKelvin) {
    return kelvin_traction(kernel.material.poisson_ratio, source, force, point, normal);
  }
  return stress_traction(kernel, source, force, point, normal);
}

Mat3 traction_map(const Kernel& kernel, const Vec3& source, const Vec3& point, const Vec3& normal) {
  Mat3 map;  // map(j, i): traction component j per unit force component i
  for (int i = 0; i < 3; ++i) {
    Vec3 unit;
    unit[i] = 1.0;
    const Vec3 t = traction(kernel, source, unit, point, normal);
    for (int j = 0; j < 3; ++j) map(j, i) = t[j];
  }
  return map;
}

}  // namespace sculpt::deform
