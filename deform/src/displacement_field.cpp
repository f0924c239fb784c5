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

// Points are processed in blocks: every source is added over the whole block (the innermost
// loop runs over points, so it vectorises), then one pass per point finishes the block. The
// loop over sources stays outside: with at most ten of them an inner loop over sources would
// be too short to vectorise. A block reads its positions in place when the points are
// contiguous (every point moves) and from a gathered copy otherwise.
constexpr std::size_t kBlock = 128;

template <typename T>
struct Block {
  std::size_t size = 0;
  const float* qx = nullptr;  // positions before the frame
  const float* qy = nullptr;
  const float* qz = nullptr;
  alignas(64) T ux[kBlock], uy[kBlock], uz[kBlock];
};

// The displacement gradient g_lm = du_l/dQ_m over a block (same formula as
// displacement_gradient), for carrying normals and for the fold guard.
template <typename T>
struct GradientBlock {
  alignas(64) T g[3][3][kBlock];
};

// One pass per source over the block adds the displacement
//   u(Q) = sum_s (alpha/r + beta/r^3) f_s + gamma/r^3 (r.f_s) r   (see KernelCoefficients)
// and, with `kGradient`, its gradient, sharing one square root and one division per point and
// source: 1/r^3 and 1/r^5 are products of 1/r, where they used to be two more divisions.
// The displacement is evaluated with exactly the operations it always was (each position is
// bit for bit what it was); the gradient, which only feeds the normals and the fold guard,
// is rearranged as g += a r^T + b f^T + (h r.f) I with
//   a = g'(r)/r f + h'(r)/r (r.f) r,  b = h r,  h = gamma/r^3,
// and fused multiply-adds (one rounding each, exact IEEE operations; the build's ISO mode does
// not contract a*b+c on its own).
template <typename T, bool kGradient, bool kFirst>
void add_source(const SourceTable<T>& t, std::size_t s, Block<T>& b, GradientBlock<T>& gb);

template <typename T, bool kGradient>
void add_sources(const SourceTable<T>& t, Block<T>& b, GradientBlock<T>& gb) {
  for (std::size_t s = 0; s < t.count; ++s) {
    if (s == 0) {
      add_source<T, kGradient, true>(t, s, b, gb);
    } else {
      add_source<T, kGradient, false>(t, s, b, gb);
    }
  }
}

// One source over the block. The first one starts the sums from zero in registers (same
// values as adding to zeroed arrays, without clearing twelve arrays per block first).
template <typename T, bool kGradient, bool kFirst>
void add_source(const SourceTable<T>& t, std::size_t s, Block<T>& b, GradientBlock<T>& gb) {
  const std::size_t n = b.size;
  const T alpha = t.alpha, beta = t.beta, gamma = t.gamma, eps2 = t.eps2;
  const T minus_alpha = -alpha, minus_3beta = -(T(3) * beta), minus_3gamma = T(-3) * gamma;
  const T px = t.px[s], py = t.py[s], pz = t.pz[s];
  const T fx = t.fx[s], fy = t.fy[s], fz = t.fz[s];
  const float* __restrict qx = b.qx;
  const float* __restrict qy = b.qy;
  const float* __restrict qz = b.qz;
  // The running sum at k; the first source reads nothing.
  auto sum = [](const T* acc, std::size_t k) {
    if constexpr (kFirst) {
      (void)acc;
      (void)k;
      return T(0);
    } else {
      return acc[k];
    }
  };
#pragma GCC ivdep
  for (std::size_t k = 0; k < n; ++k) {
    const T rx = T(qx[k]) - px, ry = T(qy[k]) - py, rz = T(qz[k]) - pz;
    const T r2 = rx * rx + ry * ry + rz * rz + eps2;
    const T inv = T(1) / std::sqrt(r2);
    const T inv2 = inv * inv;
    const T inv3 = inv2 * inv;
    const T rf = rx * fx + ry * fy + rz * fz;
    const T diag = alpha * inv + beta * inv3;
    const T h = gamma * inv3;
    const T radial = h * rf;
    b.ux[k] = sum(b.ux, k) + (diag * fx + radial * rx);
    b.uy[k] = sum(b.uy, k) + (diag * fy + radial * ry);
    b.uz[k] = sum(b.uz, k) + (diag * fz + radial * rz);
    if constexpr (kGradient) {
      const T inv5 = inv3 * inv2;
      const T g_prime = std::fma(minus_3beta, inv5, minus_alpha * inv3);
      const T h_prime_rf = minus_3gamma * inv5 * rf;
      const T ax = std::fma(g_prime, fx, h_prime_rf * rx);
      const T ay = std::fma(g_prime, fy, h_prime_rf * ry);
      const T az = std::fma(g_prime, fz, h_prime_rf * rz);
      const T bx = h * rx, by = h * ry, bz = h * rz;
      auto& g = gb.g;
      g[0][0][k] = std::fma(ax, rx, std::fma(bx, fx, sum(g[0][0], k) + radial));
      g[0][1][k] = std::fma(ax, ry, std::fma(bx, fy, sum(g[0][1], k)));
      g[0][2][k] = std::fma(ax, rz, std::fma(bx, fz, sum(g[0][2], k)));
      g[1][0][k] = std::fma(ay, rx, std::fma(by, fx, sum(g[1][0], k)));
      g[1][1][k] = std::fma(ay, ry, std::fma(by, fy, sum(g[1][1], k) + radial));
      g[1][2][k] = std::fma(ay, rz, std::fma(by, fz, sum(g[1][2], k)));
      g[2][0][k] = std::fma(az, rx, std::fma(bz, fx, sum(g[2][0], k)));
      g[2][1][k] = std::fma(az, ry, std::fma(bz, fy, sum(g[2][1], k)));
      g[2][2][k] = std::fma(az, rz, std::fma(bz, fz, sum(g[2][2], k) + radial));
    }
  }
}

// det(I + grad u) at block point k and, when `kCarry`, the block's normal k carried by
// Nanson's formula (MATH.md §6): n' = normalize(cof(Fg) n), cof(Fg) = det(Fg) Fg^-T. The
// cofactor is used as it is: where the frame folded (det <= 0) no normal formula is
// meaningful, and the fold guard rejects the frame before anyone reads that normal.
template <typename T, bool kCarry>
inline T jacobian_and_normal(const GradientBlock<T>& gb, std::size_t k, float& nx, float& ny, float& nz) {
  const T f00 = T(1) + gb.g[0][0][k], f01 = gb.g[0][1][k], f02 = gb.g[0][2][k];
  const T f10 = gb.g[1][0][k], f11 = T(1) + gb.g[1][1][k], f12 = gb.g[1][2][k];
  const T f20 = gb.g[2][0][k], f21 = gb.g[2][1][k], f22 = T(1) + gb.g[2][2][k];
  // a b - c d with one rounding less: fma(a, b, -(c d)).
  auto cross_term = [](T a, T b, T c, T d) { return std::fma(a, b, -(c * d)); };
  const T c00 = cross_term(f11, f22, f12, f21), c01 = cross_term(f12, f20, f10, f22);
  const T c02 = cross_term(f10, f21, f11, f20);
  const T det = std::fma(f00, c00, std::fma(f01, c01, f02 * c02));
  if constexpr (kCarry) {
    const T c10 = cross_term(f02, f21, f01, f22), c11 = cross_term(f00, f22, f02, f20);
    const T c12 = cross_term(f01, f20, f00, f21);
    const T c20 = cross_term(f01, f12, f02, f11), c21 = cross_term(f02, f10, f00, f12);
    const T c22 = cross_term(f00, f11, f01, f10);
    const T n0 = nx, n1 = ny, n2 = nz;
    const T mx = std::fma(c00, n0, std::fma(c01, n1, c02 * n2));
    const T my = std::fma(c10, n0, std::fma(c11, n1, c12 * n2));
    const T mz = std::fma(c20, n0, std::fma(c21, n1, c22 * n2));
    const T len2 = std::fma(mx, mx, std::fma(my, my, mz * mz));
    // A degenerate gradient keeps the old normal rather than writing NaN; selects, not a
    // branch, so the loop over a block vectorises.
    const bool usable = len2 > T(0);
    const T scale = T(1) / std::sqrt(usable ? len2 : T(1));
    nx = usable ? static_cast<float>(mx * scale) : nx;
    ny = usable ? static_cast<float>(my * scale) : ny;
    nz = usable ? static_cast<float>(mz * scale) : nz;
  }
  return det;
}

// The per-point end of a block, in place: each iteration reads its point's old position and
// normal before writing them. The arrays are distinct (model arrays or the block's copies);
// saying so lets the loop vectorise without run-time overlap checks.
template <typename T, bool kGradient, bool kCarry>
void finish_block(const GradientBlock<T>& gb, const Block<T>& b, std::size_t n, float* __restrict x,
                  float* __restrict y, float* __restrict z, float* __restrict nx, float* __restrict ny,
                  float* __restrict nz, T* __restrict dets, T* __restrict lane_min_det,
                  T* __restrict lane_max_squared) {
  for (std::size_t k = 0; k < n; ++k) {
    if constexpr (kGradient) {
      T det;
      if constexpr (kCarry) {
        det = jacobian_and_normal<T, true>(gb, k, nx[k], ny[k], nz[k]);
      } else {
        float unused = 0.0f;
        det = jacobian_and_normal<T, false>(gb, k, unused, unused, unused);
      }
      dets[k] = det;
      lane_min_det[k] = det < lane_min_det[k] ? det : lane_min_det[k];
    }
    x[k] = static_cast<float>(T(x[k]) + b.ux[k]);
    y[k] = static_cast<float>(T(y[k]) + b.uy[k]);
    z[k] = static_cast<float>(T(z[k]) + b.uz[k]);
    const T u2 = b.ux[k] * b.ux[k] + b.uy[k] * b.uy[k] + b.uz[k] * b.uz[k];
    lane_max_squared[k] = u2 > lane_max_squared[k] ? u2 : lane_max_squared[k];
  }
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
// Slot k of the journal holds the pass's k-th point, so blocks record independently (the two
// halves of a split pass write disjoint slots).
struct JournalWriter {
  UndoJournal& j;
  // kContiguous: the pass moves points 0, 1, 2, ... in order, so the journal notes that once
  // instead of writing an index per point (a 400 kB stream per frame at 100,000 points).
  // `normals`: the pass carries them (one that carries none leaves them be).
  void begin_pass(bool contiguous, bool normals, std::size_t count) const noexcept {
    j.contiguous_ = contiguous;
    j.recorded_normals_ = j.normals_ && normals;
    j.count_ = count <= j.index_.size() ? count : 0;  // more cannot happen with the reservation asked for
  }
  template <bool kContiguous, typename IndexOf>
  void record(IndexOf index_of, std::size_t begin, std::size_t n, const float* x, const float* y, const float* z,
              const float* nx, const float* ny, const float* nz) const noexcept {
    const std::size_t at = begin;
    if (at + n > j.count_) return;  // begin_pass found no room for the pass
    if constexpr (!kContiguous) {
      for (std::size_t k = 0; k < n; ++k) j.index_[at + k] = static_cast<std::uint32_t>(index_of(begin + k));
    }
    std::memcpy(j.x_.data() + at, x, n * sizeof(float));
    std::memcpy(j.y_.data() + at, y, n * sizeof(float));
    std::memcpy(j.z_.data() + at, z, n * sizeof(float));
    if (j.normals_ && nx) {
      std::memcpy(j.nx_.data() + at, nx, n * sizeof(float));
      std::memcpy(j.ny_.data() + at, ny, n * sizeof(float));
      std::memcpy(j.nz_.data() + at, nz, n * sizeof(float));
    }
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
  const bool normals = recorded_normals_ && model.has_normals();
  for (std::size_t k = 0; k < count_; ++k) {
    const std::size_t i = contiguous_ ? k : index_[k];
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

// A region block's three attributes between the model (at the indexed points) and the block's
// copy: gathered when kGather, scattered back otherwise.
template <bool kGather, typename IndexOf>
void copy_indexed(IndexOf index_of, std::size_t begin, std::size_t n, std::vector<float>& a, std::vector<float>& b,
                  std::vector<float>& c, float* ka, float* kb, float* kc) {
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = index_of(begin + k);
    if constexpr (kGather) {
      ka[k] = a[i];
      kb[k] = b[i];
      kc[k] = c[i];
    } else {
      a[i] = ka[k];
      b[i] = kb[k];
      c[i] = kc[k];
    }
  }
}

// The extremes of part of a pass, reduced across parts exactly (max and min do not depend on
// the order).
template <typename T>
struct PassExtremes {
  T max_squared = T(0);
  T min_det = T(1);
  std::uint32_t bad = 0;
};

// Each block: record the old positions (and normals) in the journal, add every source's
// displacement (and gradient) into block arrays, then one pass per point for the Jacobian, the
// carried normal, the new position and the running extremes, and a bit test for non-finite
// values. When every point moves (kContiguous) the block works in place on the model's arrays;
// otherwise on a gathered copy, scattered back at the end. The extremes are kept per block
// lane and reduced once at the end: a running scalar max/min does not vectorise without
// fast-math, lane-wise selects do, and max and min are exact whatever the order.
// Covers the pass's points first .. last - 1 (first a multiple of kBlock).
template <typename T, bool kGradient, bool kCarry, bool kContiguous, typename IndexOf>
PassExtremes<T> apply_range(PointModel& model, const SourceTable<T>& t, std::size_t first, std::size_t last,
                            IndexOf index_of, UndoJournal* journal) noexcept {
  static_assert(kGradient || !kCarry, "carrying normals needs the gradient");
  Block<T> b;
  GradientBlock<T> gb;
  alignas(64) float gx[kBlock], gy[kBlock], gz[kBlock];     // gathered positions
  alignas(64) float gnx[kBlock], gny[kBlock], gnz[kBlock];  // gathered normals
  alignas(64) T dets[kBlock];
  alignas(64) T lane_max_squared[kBlock];
  alignas(64) T lane_min_det[kBlock];
  for (std::size_t k = 0; k < kBlock; ++k) {
    lane_max_squared[k] = T(0);
    lane_min_det[k] = T(1);
  }
  std::uint32_t bad = 0;
  for (std::size_t begin = first; begin < last; begin += kBlock) {
    const std::size_t n = std::min(kBlock, last - begin);
    float *x, *y, *z, *nx = nullptr, *ny = nullptr, *nz = nullptr;
    if constexpr (kContiguous) {
      x = model.x.data() + begin;
      y = model.y.data() + begin;
      z = model.z.data() + begin;
      if constexpr (kCarry) {
        nx = model.nx.data() + begin;
        ny = model.ny.data() + begin;
        nz = model.nz.data() + begin;
      }
    } else {
      x = gx;
      y = gy;
      z = gz;
      copy_indexed<true>(index_of, begin, n, model.x, model.y, model.z, gx, gy, gz);
      if constexpr (kCarry) {
        nx = gnx;
        ny = gny;
        nz = gnz;
        copy_indexed<true>(index_of, begin, n, model.nx, model.ny, model.nz, gnx, gny, gnz);
      }
    }
    if (journal) {
      JournalWriter{*journal}.record<kContiguous>(index_of, begin, n, x, y, z, nx, ny, nz);
    }
    b.size = n;
    b.qx = x;
    b.qy = y;
    b.qz = z;
    add_sources<T, kGradient>(t, b, gb);
    finish_block<T, kGradient, kCarry>(gb, b, n, x, y, z, nx, ny, nz, dets, lane_min_det, lane_max_squared);
    if constexpr (kGradient) bad |= non_finite_bits(dets, n);
    if constexpr (kCarry) bad |= non_finite_bits(nx, n) | non_finite_bits(ny, n) | non_finite_bits(nz, n);
    bad |= non_finite_bits(x, n) | non_finite_bits(y, n) | non_finite_bits(z, n);
    if constexpr (!kContiguous) {
      copy_indexed<false>(index_of, begin, n, model.x, model.y, model.z, gx, gy, gz);
      if constexpr (kCarry) copy_indexed<false>(index_of, begin, n, model.nx, model.ny, model.nz, gnx, gny, gnz);
    }
  }
  PassExtremes<T> e;
  e.bad = bad;
  for (std::size_t k = 0; k < kBlock; ++k) {
    e.max_squared = lane_max_squared[k] > e.max_squared ? lane_max_squared[k] : e.max_squared;
    e.min_det = lane_min_det[k] < e.min_det ? lane_min_det[k] : e.min_det;
  }
  return e;
}

// Below this many points a pass runs on the caller alone: waking the worker costs microseconds.
constexpr std::size_t kMinSplitPoints = 16384;

// A pass over `count` points, split at a block boundary between the caller and the worker when
// there is one and the pass is large enough.
template <typename T, bool kGradient, bool kCarry, bool kContiguous, typename IndexOf>
FieldResult apply_typed(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                        UndoJournal* journal, FieldWorker* worker) {
  if (journal) JournalWriter{*journal}.begin_pass(kContiguous, kCarry, count);
  PassExtremes<T> e;
  if (!worker || count < kMinSplitPoints) {
    e = apply_range<T, kGradient, kCarry, kContiguous>(model, t, 0, count, index_of, journal);
  } else {
    struct Halves {
      PointModel& model;
      const SourceTable<T>& table;
      IndexOf index_of;
      UndoJournal* journal;
      std::size_t split, count;
      PassExtremes<T> part[2];
    } halves{model, t, index_of, journal, (count / 2 + kBlock - 1) / kBlock * kBlock, count, {}};
    worker->run_both(
        [](void* context, int part) noexcept {
          Halves& h = *static_cast<Halves*>(context);
          const std::size_t first = part == 0 ? 0 : h.split, last = part == 0 ? h.split : h.count;
          h.part[part] =
              apply_range<T, kGradient, kCarry, kContiguous>(h.model, h.table, first, last, h.index_of, h.journal);
        },
        &halves);
    e.max_squared = std::max(halves.part[0].max_squared, halves.part[1].max_squared);
    e.min_det = std::min(halves.part[0].min_det, halves.part[1].min_det);
    e.bad = halves.part[0].bad | halves.part[1].bad;
  }
  FieldResult result;
  result.finite = e.bad == 0 && std::isfinite(static_cast<double>(e.max_squared));
  result.max_displacement = std::sqrt(static_cast<double>(e.max_squared));
  result.min_jacobian = static_cast<double>(e.min_det);
  return result;
}

// The three loop variants as compile-time choices, so none of them tests a flag per point.
template <typename T, bool kContiguous, typename IndexOf>
FieldResult apply_variant(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                          bool carry_normals, bool jacobian, UndoJournal* journal, FieldWorker* worker) {
  if (carry_normals) return apply_typed<T, true, true, kContiguous>(model, t, count, index_of, journal, worker);
  if (jacobian) return apply_typed<T, true, false, kContiguous>(model, t, count, index_of, journal, worker);
  return apply_typed<T, false, false, kContiguous>(model, t, count, index_of, journal, worker);
}

template <typename T>
FieldResult apply_in(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                     std::span<const std::uint32_t> indices, bool all_points, bool carry_normals, bool jacobian,
                     UndoJournal* journal, FieldWorker* worker) {
  const SourceTable<T> table = make_table<T>(kernel, sources);
  if (all_points) {
    return apply_variant<T, true>(
        model, table, model.size(), [](std::size_t k) { return k; }, carry_normals, jacobian, journal, worker);
  }
  const std::uint32_t* idx = indices.data();
  return apply_variant<T, false>(
      model, table, indices.size(), [idx](std::size_t k) { return std::size_t{idx[k]}; }, carry_normals, jacobian,
      journal, worker);
}

}  // namespace

FieldResult apply_displacements(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                                std::span<const std::uint32_t> indices, bool all_points, const FieldOptions& options,
                                bool jacobian, UndoJournal* journal, FieldWorker* worker) noexcept {
  if (journal) journal->clear();
  if (sources.empty()) return {};
  const bool normals = options.carry_normals && model.has_normals();
  if (options.precision == Precision::kDouble) {
    return apply_in<double>(model, kernel, sources, indices, all_points, normals, jacobian, journal, worker);
  }
  return apply_in<float>(model, kernel, sources, indices, all_points, normals, jacobian, journal, worker);
}

}  // namespace sculpt::deform
