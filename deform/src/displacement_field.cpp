#include "sculpt/deform/displacement_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

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

// Points are processed in blocks: positions are gathered into small stack arrays, every source
// is added over the whole block (the innermost loop runs over points, so it vectorises), then
// the block is written back. The loop over sources stays outside: with at most ten of them an
// inner loop over sources would be too short to vectorise.
constexpr std::size_t kBlock = 128;

template <typename T>
struct Block {
  std::size_t size = 0;
  alignas(64) T qx[kBlock], qy[kBlock], qz[kBlock];
  alignas(64) T ux[kBlock], uy[kBlock], uz[kBlock];
};

// u(Q) = sum_s (alpha/r + beta/r^3) f_s + gamma/r^3 (r.f_s) r; see KernelCoefficients.
template <typename T>
void add_displacements(const SourceTable<T>& t, Block<T>& b) {
  for (std::size_t k = 0; k < b.size; ++k) b.ux[k] = b.uy[k] = b.uz[k] = T(0);
  for (std::size_t s = 0; s < t.count; ++s) {
    const T px = t.px[s], py = t.py[s], pz = t.pz[s];
    const T fx = t.fx[s], fy = t.fy[s], fz = t.fz[s];
    const T alpha = t.alpha, beta = t.beta, gamma = t.gamma, eps2 = t.eps2;
#pragma GCC ivdep
    for (std::size_t k = 0; k < b.size; ++k) {
      const T rx = b.qx[k] - px, ry = b.qy[k] - py, rz = b.qz[k] - pz;
      const T r2 = rx * rx + ry * ry + rz * rz + eps2;
      const T inv = T(1) / std::sqrt(r2);
      const T inv3 = inv * inv * inv;
      const T rf = rx * fx + ry * fy + rz * fz;
      const T diag = alpha * inv + beta * inv3;
      const T radial = gamma * inv3 * rf;
      b.ux[k] += diag * fx + radial * rx;
      b.uy[k] += diag * fy + radial * ry;
      b.uz[k] += diag * fz + radial * rz;
    }
  }
}

// The displacement gradient g_lm = du_l/dQ_m over a block (same formula as
// displacement_gradient), for carrying normals.
template <typename T>
struct GradientBlock {
  alignas(64) T g[3][3][kBlock];
};

template <typename T>
void add_gradients(const SourceTable<T>& t, const Block<T>& b, GradientBlock<T>& gb) {
  for (int l = 0; l < 3; ++l)
    for (int m = 0; m < 3; ++m)
      for (std::size_t k = 0; k < b.size; ++k) gb.g[l][m][k] = T(0);
  for (std::size_t s = 0; s < t.count; ++s) {
    const T px = t.px[s], py = t.py[s], pz = t.pz[s];
    const T f[3] = {t.fx[s], t.fy[s], t.fz[s]};
    for (std::size_t k = 0; k < b.size; ++k) {
      const T r[3] = {b.qx[k] - px, b.qy[k] - py, b.qz[k] - pz};
      const T r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + t.eps2;
      const T inv = T(1) / std::sqrt(r2);
      const T inv3 = inv / r2;
      const T inv5 = inv3 / r2;
      const T rf = r[0] * f[0] + r[1] * f[1] + r[2] * f[2];
      const T h = t.gamma * inv3;
      const T g_prime = -t.alpha * inv3 - T(3) * t.beta * inv5;
      const T h_prime = T(-3) * t.gamma * inv5;
      for (int l = 0; l < 3; ++l) {
        for (int m = 0; m < 3; ++m) {
          gb.g[l][m][k] += g_prime * f[l] * r[m] + h_prime * rf * r[l] * r[m] + h * r[l] * f[m];
        }
        gb.g[l][l][k] += h * rf;
      }
    }
  }
}

// det(I + grad u) at block point k and, when `carry`, the block's normal k carried by Nanson's
// formula (MATH.md §6): n' = normalize(cof(Fg) n), cof(Fg) = det(Fg) Fg^-T. The cofactor is
// used as it is: where the frame folded (det <= 0) no normal formula is meaningful, and the
// fold guard rejects the frame before anyone reads that normal.
template <typename T>
inline T jacobian_and_normal(const GradientBlock<T>& gb, std::size_t k, bool carry, float& nx, float& ny, float& nz) {
  const T f00 = T(1) + gb.g[0][0][k], f01 = gb.g[0][1][k], f02 = gb.g[0][2][k];
  const T f10 = gb.g[1][0][k], f11 = T(1) + gb.g[1][1][k], f12 = gb.g[1][2][k];
  const T f20 = gb.g[2][0][k], f21 = gb.g[2][1][k], f22 = T(1) + gb.g[2][2][k];
  const T c00 = f11 * f22 - f12 * f21, c01 = f12 * f20 - f10 * f22, c02 = f10 * f21 - f11 * f20;
  const T det = f00 * c00 + f01 * c01 + f02 * c02;
  if (!carry) return det;
  const T c10 = f02 * f21 - f01 * f22, c11 = f00 * f22 - f02 * f20, c12 = f01 * f20 - f00 * f21;
  const T c20 = f01 * f12 - f02 * f11, c21 = f02 * f10 - f00 * f12, c22 = f00 * f11 - f01 * f10;
  const T n0 = nx, n1 = ny, n2 = nz;
  const T mx = c00 * n0 + c01 * n1 + c02 * n2;
  const T my = c10 * n0 + c11 * n1 + c12 * n2;
  const T mz = c20 * n0 + c21 * n1 + c22 * n2;
  const T len2 = mx * mx + my * my + mz * mz;
  // A degenerate gradient keeps the old normal rather than writing NaN; selects, not a branch,
  // so the loop over a block vectorises.
  const bool usable = len2 > T(0);
  const T scale = T(1) / std::sqrt(usable ? len2 : T(1));
  nx = usable ? static_cast<float>(mx * scale) : nx;
  ny = usable ? static_cast<float>(my * scale) : ny;
  nz = usable ? static_cast<float>(mz * scale) : nz;
  return det;
}

// Non-zero when any of the n values is infinite or NaN (all exponent bits set). Integer OR
// reductions may be reordered, so this vectorises where a float sum would not.
template <typename T>
std::uint32_t non_finite_bits(const T* v, std::size_t n) {
  static_assert(sizeof(T) == 4 || sizeof(T) == 8, "float or double");
  using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  constexpr Bits kExponent = static_cast<Bits>(sizeof(T) == 4 ? 0x7f800000ull : 0x7ff0000000000000ull);
  std::uint32_t bad = 0;
  for (std::size_t k = 0; k < n; ++k) {
    Bits bits;
    std::memcpy(&bits, v + k, sizeof bits);
    bad |= static_cast<std::uint32_t>((bits & kExponent) == kExponent);
  }
  return bad;
}

}  // namespace

// Records a block of old values into a journal reserved at set-up: no allocation, by
// construction of the reservation (the caller reserves for every point a frame may move).
struct JournalWriter {
  UndoJournal& j;
  template <typename IndexOf>
  void record(IndexOf index_of, std::size_t begin, std::size_t n, const float* x, const float* y, const float* z,
              const float* nx, const float* ny, const float* nz) const noexcept {
    const std::size_t at = j.count_;
    if (at + n > j.index_.size()) return;  // cannot happen with the reservation the contract asks for
    for (std::size_t k = 0; k < n; ++k) j.index_[at + k] = static_cast<std::uint32_t>(index_of(begin + k));
    std::memcpy(j.x_.data() + at, x, n * sizeof(float));
    std::memcpy(j.y_.data() + at, y, n * sizeof(float));
    std::memcpy(j.z_.data() + at, z, n * sizeof(float));
    if (j.normals_ && nx) {
      std::memcpy(j.nx_.data() + at, nx, n * sizeof(float));
      std::memcpy(j.ny_.data() + at, ny, n * sizeof(float));
      std::memcpy(j.nz_.data() + at, nz, n * sizeof(float));
    }
    j.count_ = at + n;
  }
};

void UndoJournal::reserve(std::size_t points, bool normals) {
  normals_ = normals;
  count_ = 0;
  index_.assign(points, 0);
  x_.assign(points, 0.0f);
  y_.assign(points, 0.0f);
  z_.assign(points, 0.0f);
  nx_.assign(normals ? points : 0, 0.0f);
  ny_.assign(normals ? points : 0, 0.0f);
  nz_.assign(normals ? points : 0, 0.0f);
}

void UndoJournal::restore(PointModel& model) const noexcept {
  const bool normals = normals_ && model.has_normals();
  for (std::size_t k = 0; k < count_; ++k) {
    const std::size_t i = index_[k];
    model.x[i] = x_[k];
    model.y[i] = y_[k];
    model.z[i] = z_[k];
    if (normals) {
      model.nx[i] = nx_[k];
      model.ny[i] = ny_[k];
      model.nz[i] = nz_[k];
    }
  }
}

namespace {

// Each block: gather positions (and normals), record them in the journal, compute the
// displacements (and gradient, Jacobian, carried normals) into block arrays, check the block
// for non-finite values with a bit test, then scatter it back.
template <typename T, typename IndexOf>
FieldResult apply_typed(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                        bool carry_normals, bool jacobian, UndoJournal* journal) {
  float* __restrict x = model.x.data();
  float* __restrict y = model.y.data();
  float* __restrict z = model.z.data();
  Block<T> b;
  GradientBlock<T> gb;
  alignas(64) float px[kBlock], py[kBlock], pz[kBlock];  // new positions
  alignas(64) float ox[kBlock], oy[kBlock], oz[kBlock];  // old positions, for the journal
  alignas(64) float nx[kBlock], ny[kBlock], nz[kBlock];  // normals, old then carried
  alignas(64) T dets[kBlock];
  T max_squared = T(0);
  T min_det = T(1);
  std::uint32_t bad = 0;
  const bool gradients = carry_normals || jacobian;
  if (journal) journal->clear();
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    b.size = n;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = index_of(begin + k);
      ox[k] = x[i];
      oy[k] = y[i];
      oz[k] = z[i];
      b.qx[k] = ox[k];
      b.qy[k] = oy[k];
      b.qz[k] = oz[k];
    }
    if (carry_normals) {
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = index_of(begin + k);
        nx[k] = model.nx[i];
        ny[k] = model.ny[i];
        nz[k] = model.nz[i];
      }
    }
    if (journal) {
      JournalWriter{*journal}.record(index_of, begin, n, ox, oy, oz, carry_normals ? nx : nullptr, ny, nz);
    }
    add_displacements(t, b);
    if (gradients) {
      add_gradients(t, b, gb);
      if (carry_normals) {
        for (std::size_t k = 0; k < n; ++k) dets[k] = jacobian_and_normal(gb, k, true, nx[k], ny[k], nz[k]);
      } else {
        float unused = 0.0f;
        for (std::size_t k = 0; k < n; ++k) dets[k] = jacobian_and_normal(gb, k, false, unused, unused, unused);
      }
      for (std::size_t k = 0; k < n; ++k) min_det = std::min(min_det, dets[k]);
      bad |= non_finite_bits(dets, n);
      if (carry_normals) bad |= non_finite_bits(nx, n) | non_finite_bits(ny, n) | non_finite_bits(nz, n);
    }
    for (std::size_t k = 0; k < n; ++k) {
      px[k] = static_cast<float>(b.qx[k] + b.ux[k]);
      py[k] = static_cast<float>(b.qy[k] + b.uy[k]);
      pz[k] = static_cast<float>(b.qz[k] + b.uz[k]);
      const T u2 = b.ux[k] * b.ux[k] + b.uy[k] * b.uy[k] + b.uz[k] * b.uz[k];
      max_squared = u2 > max_squared ? u2 : max_squared;
    }
    bad |= non_finite_bits(px, n) | non_finite_bits(py, n) | non_finite_bits(pz, n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = index_of(begin + k);
      x[i] = px[k];
      y[i] = py[k];
      z[i] = pz[k];
    }
    if (carry_normals) {
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = index_of(begin + k);
        model.nx[i] = nx[k];
        model.ny[i] = ny[k];
        model.nz[i] = nz[k];
      }
    }
  }
  FieldResult result;
  result.finite = bad == 0 && std::isfinite(static_cast<double>(max_squared));
  result.max_displacement = std::sqrt(static_cast<double>(max_squared));
  result.min_jacobian = static_cast<double>(min_det);
  return result;
}

template <typename T>
FieldResult apply_in(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                     std::span<const std::uint32_t> indices, bool all_points, bool carry_normals, bool jacobian,
                     UndoJournal* journal) {
  const SourceTable<T> table = make_table<T>(kernel, sources);
  if (all_points) {
    return apply_typed(
        model, table, model.size(), [](std::size_t k) { return k; }, carry_normals, jacobian, journal);
  }
  const std::uint32_t* idx = indices.data();
  return apply_typed(
      model, table, indices.size(), [idx](std::size_t k) { return std::size_t{idx[k]}; }, carry_normals, jacobian,
      journal);
}

}  // namespace

FieldResult apply_displacements(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                                std::span<const std::uint32_t> indices, bool all_points, const FieldOptions& options,
                                bool jacobian, UndoJournal* journal) noexcept {
  if (journal) journal->clear();
  if (sources.empty()) return {};
  const bool normals = options.carry_normals && model.has_normals();
  if (options.precision == Precision::kDouble) {
    return apply_in<double>(model, kernel, sources, indices, all_points, normals, jacobian, journal);
  }
  return apply_in<float>(model, kernel, sources, indices, all_points, normals, jacobian, journal);
}

}  // namespace sculpt::deform
