#include "sculpt/deform/displacement_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace sculpt::deform {
namespace {

// Per-source constants in the loop's precision, laid out as small arrays so the inner loop over
// sources is fully unrolled-friendly and the outer loop over points vectorises.
template <typename T>
struct SourceTable {
  std::size_t count = 0;
  std::array<T, kMaxSources> px{}, py{}, pz{};  // source position
  std::array<T, kMaxSources> fx{}, fy{}, fz{};  // effective force
  T alpha{}, beta{}, gamma{}, eps2{};
};

template <typename T>
SourceTable<T> make_table(const Kernel& kernel, std::span<const SourceForce> sources) {
  SourceTable<T> t;
  t.count = std::min(sources.size(), kMaxSources);
  for (std::size_t s = 0; s < t.count; ++s) {
    t.px[s] = static_cast<T>(sources[s].source.x);
    t.py[s] = static_cast<T>(sources[s].source.y);
    t.pz[s] = static_cast<T>(sources[s].source.z);
    t.fx[s] = static_cast<T>(sources[s].force.x);
    t.fy[s] = static_cast<T>(sources[s].force.y);
    t.fz[s] = static_cast<T>(sources[s].force.z);
  }
  const KernelCoefficients k = coefficients(kernel);
  t.alpha = static_cast<T>(k.alpha);
  t.beta = static_cast<T>(k.beta);
  t.gamma = static_cast<T>(k.gamma);
  t.eps2 = static_cast<T>(k.eps_squared);
  return t;
}

// u(Q) = sum_s (alpha/r + beta/r^3) f_s + gamma/r^3 (r.f_s) r; see KernelCoefficients.
template <typename T>
inline void displacement_at(const SourceTable<T>& t, T qx, T qy, T qz, T& ux, T& uy, T& uz) {
  ux = uy = uz = T(0);
  for (std::size_t s = 0; s < t.count; ++s) {
    const T rx = qx - t.px[s], ry = qy - t.py[s], rz = qz - t.pz[s];
    const T r2 = rx * rx + ry * ry + rz * rz + t.eps2;
    const T inv = T(1) / std::sqrt(r2);
    const T inv3 = inv * inv * inv;
    const T rf = rx * t.fx[s] + ry * t.fy[s] + rz * t.fz[s];
    const T diag = t.alpha * inv + t.beta * inv3;
    const T radial = t.gamma * inv3 * rf;
    ux += diag * t.fx[s] + radial * rx;
    uy += diag * t.fy[s] + radial * ry;
    uz += diag * t.fz[s] + radial * rz;
  }
}

// Displacement and its gradient g[l][m] = du_l/dQ_m (same formula as displacement_gradient).
template <typename T>
inline void displacement_and_gradient_at(const SourceTable<T>& t, T qx, T qy, T qz, T u[3],
                                         T g[3][3]) {
  for (int l = 0; l < 3; ++l) {
    u[l] = T(0);
    for (int m = 0; m < 3; ++m) g[l][m] = T(0);
  }
  for (std::size_t s = 0; s < t.count; ++s) {
    const T r[3] = {qx - t.px[s], qy - t.py[s], qz - t.pz[s]};
    const T f[3] = {t.fx[s], t.fy[s], t.fz[s]};
    const T r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + t.eps2;
    const T inv = T(1) / std::sqrt(r2);
    const T inv3 = inv / r2;
    const T inv5 = inv3 / r2;
    const T rf = r[0] * f[0] + r[1] * f[1] + r[2] * f[2];
    const T diag = t.alpha * inv + t.beta * inv3;
    const T h = t.gamma * inv3;
    const T g_prime = -t.alpha * inv3 - T(3) * t.beta * inv5;
    const T h_prime = T(-3) * t.gamma * inv5;
    for (int l = 0; l < 3; ++l) {
      u[l] += diag * f[l] + h * rf * r[l];
      for (int m = 0; m < 3; ++m) {
        g[l][m] += g_prime * f[l] * r[m] + h_prime * rf * r[l] * r[m] + h * r[l] * f[m];
      }
      g[l][l] += h * rf;
    }
  }
}

// n' = normalize(F^-T n) with F = I + grad u. F^-T = cof(F) / det F, so the cofactor matrix
// suffices; the sign of det keeps the normal's side when an extreme edit inverts the element.
template <typename T>
inline void carry_normal(const T g[3][3], T& nx, T& ny, T& nz) {
  const T f00 = T(1) + g[0][0], f01 = g[0][1], f02 = g[0][2];
  const T f10 = g[1][0], f11 = T(1) + g[1][1], f12 = g[1][2];
  const T f20 = g[2][0], f21 = g[2][1], f22 = T(1) + g[2][2];
  const T c00 = f11 * f22 - f12 * f21, c01 = f12 * f20 - f10 * f22, c02 = f10 * f21 - f11 * f20;
  const T c10 = f02 * f21 - f01 * f22, c11 = f00 * f22 - f02 * f20, c12 = f01 * f20 - f00 * f21;
  const T c20 = f01 * f12 - f02 * f11, c21 = f02 * f10 - f00 * f12, c22 = f00 * f11 - f01 * f10;
  const T det = f00 * c00 + f01 * c01 + f02 * c02;
  T mx = c00 * nx + c01 * ny + c02 * nz;
  T my = c10 * nx + c11 * ny + c12 * nz;
  T mz = c20 * nx + c21 * ny + c22 * nz;
  const T len = std::sqrt(mx * mx + my * my + mz * mz);
  if (!(len > T(0))) return;  // degenerate gradient: keep the old normal rather than write NaN
  const T scale = (det < T(0) ? T(-1) : T(1)) / len;
  nx = mx * scale;
  ny = my * scale;
  nz = mz * scale;
}

template <typename T, typename IndexOf>
double apply_typed(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                   bool carry_normals) {
  float* __restrict x = model.x.data();
  float* __restrict y = model.y.data();
  float* __restrict z = model.z.data();
  T max_squared = T(0);
  if (!carry_normals) {
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = index_of(k);
      T ux, uy, uz;
      displacement_at(t, T(x[i]), T(y[i]), T(z[i]), ux, uy, uz);
      x[i] = static_cast<float>(T(x[i]) + ux);
      y[i] = static_cast<float>(T(y[i]) + uy);
      z[i] = static_cast<float>(T(z[i]) + uz);
      max_squared = std::max(max_squared, ux * ux + uy * uy + uz * uz);
    }
  } else {
    float* __restrict nx = model.nx.data();
    float* __restrict ny = model.ny.data();
    float* __restrict nz = model.nz.data();
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = index_of(k);
      T u[3], g[3][3];
      displacement_and_gradient_at(t, T(x[i]), T(y[i]), T(z[i]), u, g);
      T n0 = nx[i], n1 = ny[i], n2 = nz[i];
      carry_normal(g, n0, n1, n2);
      nx[i] = static_cast<float>(n0);
      ny[i] = static_cast<float>(n1);
      nz[i] = static_cast<float>(n2);
      x[i] = static_cast<float>(T(x[i]) + u[0]);
      y[i] = static_cast<float>(T(y[i]) + u[1]);
      z[i] = static_cast<float>(T(z[i]) + u[2]);
      max_squared = std::max(max_squared, u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    }
  }
  return std::sqrt(static_cast<double>(max_squared));
}

template <typename T>
double apply_in(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                std::span<const std::uint32_t> indices, bool all_points, bool carry_normals) {
  const SourceTable<T> table = make_table<T>(kernel, sources);
  if (all_points) {
    return apply_typed(model, table, model.size(), [](std::size_t k) { return k; }, carry_normals);
  }
  const std::uint32_t* idx = indices.data();
  return apply_typed(model, table, indices.size(), [idx](std::size_t k) { return idx[k]; },
                     carry_normals);
}

}  // namespace

double apply_displacements(PointModel& model, const Kernel& kernel,
                           std::span<const SourceForce> sources,
                           std::span<const std::uint32_t> indices, bool all_points,
                           const FieldOptions& options) noexcept {
  if (sources.empty()) return 0.0;
  const bool normals = options.carry_normals && model.has_normals();
  if (options.precision == Precision::kDouble) {
    return apply_in<double>(model, kernel, sources, indices, all_points, normals);
  }
  return apply_in<float>(model, kernel, sources, indices, all_points, normals);
}

}  // namespace sculpt::deform
