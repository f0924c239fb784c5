#include "sculpt/deform/displacement_field.hpp"

#include "lane_vector.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace sculpt::deform {
namespace {

// Per-source constants in the loop's precision, laid out as small arrays so the inner loop over
// sources is fully unrolled-friendly and the outer loop over points vectorises.
template <typename T>
struct SourceTable {
  std::size_t count = 0;
  std::array<T, kMaxSources> px{}, py{}, pz{};     // source position
  std::array<T, kMaxSources> fx{}, fy{}, fz{};     // effective force
  std::array<T, kMaxSources> gfx{}, gfy{}, gfz{};  // gamma times it, for gamma (r.f) in one dot product
  // The bound on each source's ||grad u||_2 is bound_r2 / r_eps^2 + bound_r4 / r_eps^4
  // (FieldOptions::normal_skip_bound; the README's physics notes derive it).
  std::array<T, kMaxSources> bound_r2{}, bound_r4{};
  T alpha{}, beta{}, gamma{}, eps2{};
  T skip_bound{};  // 0: every gradient is computed
  // FieldOptions::fast_inverse_sqrt: 1/r from lanes::inverse_sqrt_estimate() (float only).
  bool fast_inverse_sqrt = false;
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
  for (std::size_t s = 0; s < t.count; ++s) {
    t.gfx[s] = static_cast<T>(k.gamma * sources[s].force.x);
    t.gfy[s] = static_cast<T>(k.gamma * sources[s].force.y);
    t.gfz[s] = static_cast<T>(k.gamma * sources[s].force.z);
    const double f = norm(sources[s].force);
    t.bound_r2[s] = static_cast<T>(f * (std::abs(k.alpha) + 5.0 * std::abs(k.gamma)));
    t.bound_r4[s] = static_cast<T>(f * 3.0 * std::abs(k.beta));
  }
  return t;
}

// A pass works through its points a block at a time: a block is where a region pass gathers its
// points' positions and normals (scattering them back after), and the journal's unit. Within a
// block, the sums over the sources stay in registers (move_lanes).
constexpr std::size_t kBlock = 128;

// A fused multiply-add, a square root and c in every lane, of lanes U (short names: the
// formulas below read as formulas).
template <typename U>
[[gnu::always_inline]] inline U fused(U a, U b, U c) {
  return lanes::fma(a, b, c);
}

template <typename U>
[[gnu::always_inline]] inline U root(U a) {
  return lanes::sqrt(a);
}

template <typename U, typename T>
[[gnu::always_inline]] inline U every(T c) {
  return lanes::splat<U>(c);
}

// |r|^2 + eps^2 and a dot product, with the fused multiply-adds written out (the library does
// not let the compiler contract): every pass computes them here, so all give the same bits.
template <typename U, typename T>
[[gnu::always_inline]] inline U squared_distance(U rx, U ry, U rz, T eps2) {
  return fused(rz, rz, fused(ry, ry, rx * rx)) + eps2;
}

template <typename U, typename V>
[[gnu::always_inline]] inline U dot(U ax, U ay, U az, V bx, V by, V bz) {
  return fused(az, every<U>(bz), fused(ay, every<U>(by), ax * bx));
}

// One source's share at a register of points (U: lanes of T), from
// r = Q - P and inv = 1/sqrt(r.r + eps^2): add_displacement adds the displacement
//   u(Q) = sum_s (alpha/r + beta/r^3) f_s + gamma/r^3 (r.f_s) r   (see KernelCoefficients)
// to u, add_gradient its gradient to g, sharing the one square root and division: 1/r^3 and
// 1/r^5 are products of 1/r. The gradient, which only feeds the normals and the fold guard, is
// rearranged as g += a r^T + b f^T + (h r.f) I with
//   a = g'(r)/r f + h'(r)/r (r.f) r,  b = h r,  h = gamma/r^3,
// and fused multiply-adds (one rounding each, exact IEEE operations; the library is built with
// -ffp-contract=off, so the compiler fuses nothing else). Every pass calls these, so a point
// moves by the same bits whichever pass computed it; called together (add_share), the compiler
// computes the terms they share once.
template <typename T, typename U>
[[gnu::always_inline]] inline void add_displacement(const SourceTable<T>& t, std::size_t s, U rx, U ry, U rz, U inv,
                                                    U (&u)[3]) {
  const U fx = every<U>(t.fx[s]), fy = every<U>(t.fy[s]), fz = every<U>(t.fz[s]);
  const U inv3 = (inv * inv) * inv;
  const U gamma_rf = dot(rx, ry, rz, every<U>(t.gfx[s]), every<U>(t.gfy[s]), every<U>(t.gfz[s]));
  const U diag = fused(every<U>(t.beta), inv3, t.alpha * inv);
  const U radial = inv3 * gamma_rf;
  u[0] = fused(radial, rx, fused(diag, fx, u[0]));
  u[1] = fused(radial, ry, fused(diag, fy, u[1]));
  u[2] = fused(radial, rz, fused(diag, fz, u[2]));
}

template <typename T, typename U>
[[gnu::always_inline]] inline void add_gradient(const SourceTable<T>& t, std::size_t s, U rx, U ry, U rz, U inv,
                                                U (&g)[3][3]) {
  const U fx = every<U>(t.fx[s]), fy = every<U>(t.fy[s]), fz = every<U>(t.fz[s]);
  const U inv2 = inv * inv;
  const U inv3 = inv2 * inv;
  const U gamma_rf = dot(rx, ry, rz, every<U>(t.gfx[s]), every<U>(t.gfy[s]), every<U>(t.gfz[s]));
  const U h = t.gamma * inv3;
  const U radial = inv3 * gamma_rf;
  const U inv5 = inv3 * inv2;
  const U g_prime = fused(every<U>(-(T(3) * t.beta)), inv5, -t.alpha * inv3);
  const U h_prime_rf = (T(-3) * inv5) * gamma_rf;
  const U ax = fused(g_prime, fx, h_prime_rf * rx);
  const U ay = fused(g_prime, fy, h_prime_rf * ry);
  const U az = fused(g_prime, fz, h_prime_rf * rz);
  const U bx = h * rx, by = h * ry, bz = h * rz;
  // Written out: with the diagonal chosen by a scalar condition between lane values
  // (`l == m ? g + radial : g`, in a loop), GCC 12 at -O3 kept the radial term in lane 0 only
  // (the field tests caught it).
  g[0][0] = fused(ax, rx, fused(bx, fx, g[0][0] + radial));
  g[0][1] = fused(ax, ry, fused(bx, fy, g[0][1]));
  g[0][2] = fused(ax, rz, fused(bx, fz, g[0][2]));
  g[1][0] = fused(ay, rx, fused(by, fx, g[1][0]));
  g[1][1] = fused(ay, ry, fused(by, fy, g[1][1] + radial));
  g[1][2] = fused(ay, rz, fused(by, fz, g[1][2]));
  g[2][0] = fused(az, rx, fused(bz, fx, g[2][0]));
  g[2][1] = fused(az, ry, fused(bz, fy, g[2][1]));
  g[2][2] = fused(az, rz, fused(bz, fz, g[2][2] + radial));
}

template <typename T, bool kGradient, typename U>
[[gnu::always_inline]] inline void add_share(const SourceTable<T>& t, std::size_t s, U rx, U ry, U rz, U inv, U (&u)[3],
                                             U (&g)[3][3]) {
  add_displacement(t, s, rx, ry, rz, inv, u);
  if constexpr (kGradient) add_gradient(t, s, rx, ry, rz, inv, g);
}

// det(I + grad u) from the gradient g of a register of points (U: lanes of T) and, when
// `kCarry`, the normal (n0, n1, n2) carried by Nanson's formula (MATH.md §6):
// n' = normalize(cof(Fg) n), cof(Fg) = det(Fg) Fg^-T. The cofactor is used as it is: where the
// frame folded (det <= 0) no normal formula is meaningful, and the fold guard rejects the frame
// before anyone reads that normal.
template <typename T, bool kCarry, typename U>
[[gnu::always_inline]] inline U jacobian_and_normal(const U (&g)[3][3], U& n0, U& n1, U& n2) {
  const U f00 = T(1) + g[0][0], f01 = g[0][1], f02 = g[0][2];
  const U f10 = g[1][0], f11 = T(1) + g[1][1], f12 = g[1][2];
  const U f20 = g[2][0], f21 = g[2][1], f22 = T(1) + g[2][2];
  // a b - c d with one rounding less: fma(a, b, -(c d)).
  auto cross_term = [](U a, U b, U c, U d) { return fused(a, b, -(c * d)); };
  const U c00 = cross_term(f11, f22, f12, f21), c01 = cross_term(f12, f20, f10, f22);
  const U c02 = cross_term(f10, f21, f11, f20);
  const U det = fused(f00, c00, fused(f01, c01, f02 * c02));
  if constexpr (kCarry) {
    const U c10 = cross_term(f02, f21, f01, f22), c11 = cross_term(f00, f22, f02, f20);
    const U c12 = cross_term(f01, f20, f00, f21);
    const U c20 = cross_term(f01, f12, f02, f11), c21 = cross_term(f02, f10, f00, f12);
    const U c22 = cross_term(f00, f11, f01, f10);
    const U mx = fused(c00, n0, fused(c01, n1, c02 * n2));
    const U my = fused(c10, n0, fused(c11, n1, c12 * n2));
    const U mz = fused(c20, n0, fused(c21, n1, c22 * n2));
    const U len2 = fused(mx, mx, fused(my, my, mz * mz));
    // A degenerate gradient keeps the old normal rather than writing NaN; selects, not a
    // branch, so the loop over a block vectorises.
    const auto usable = len2 > T(0);
    const U scale = T(1) / root(usable ? len2 : every<U>(T(1)));
    n0 = usable ? mx * scale : n0;
    n1 = usable ? my * scale : n1;
    n2 = usable ? mz * scale : n2;
  }
  return det;
}

struct SkipStats {
  std::size_t skipped = 0;
  double max_skipped_bound = 0.0;
  double min_det_floor = 1.0;
};

// The extremes of a bounded pass's skipped points, kept per block lane (a scalar running max does
// not vectorise) and reduced once at the end.
template <typename T>
struct SkipLanes {
  alignas(64) T max_bound[kBlock];
  alignas(64) T min_det_floor[kBlock];
  SkipLanes() {
    for (std::size_t k = 0; k < kBlock; ++k) {
      max_bound[k] = T(0);
      min_det_floor[k] = T(1);
    }
  }
  void add_to(SkipStats& s) const {
    for (std::size_t k = 0; k < kBlock; ++k) {
      s.max_skipped_bound = std::max(s.max_skipped_bound, static_cast<double>(max_bound[k]));
      s.min_det_floor = std::min(s.min_det_floor, static_cast<double>(min_det_floor[k]));
    }
  }
};

// A point's six attributes: positions, and normals when the pass carries them.
struct PointArrays {
  float *x, *y, *z, *nx, *ny, *nz;
  PointArrays at(std::size_t k) const {
    return {x + k, y + k, z + k, nx ? nx + k : nullptr, ny ? ny + k : nullptr, nz ? nz + k : nullptr};
  }
};

// The running extremes of a pass, per block lane: move_lanes updates the lanes of its register.
template <typename T>
struct LaneExtremes {
  T* min_det;
  T* max_squared;
  SkipLanes<T>* skip;  // a bounded pass's skipped points
};

template <typename T>
using Lanes = lanes::Value<T>;
template <typename T>
using LaneBits = typename lanes::LaneTypes<T>::Bits;

// One source's 1/r at a register of points, r = Q - P: 1/sqrt(|r|^2 + eps^2), or with kFast
// (FieldOptions::fast_inverse_sqrt, float only) the processor's estimate refined.
template <bool kFast, typename T>
[[gnu::always_inline]] inline Lanes<T> reciprocal_distance(const SourceTable<T>& t, const Lanes<T>& rx,
                                                           const Lanes<T>& ry, const Lanes<T>& rz) {
  if constexpr (kFast) {
    return lanes::inverse_sqrt_estimate(squared_distance(rx, ry, rz, t.eps2));
  } else {
    return T(1) / lanes::sqrt(squared_distance(rx, ry, rz, t.eps2));
  }
}

// Every source's 1/r at a register of points, first: the square roots and divisions of the
// sources are independent and overlap the gradient's long arithmetic, where one chain per
// source left the core waiting.
template <typename T>
[[gnu::always_inline]] inline void reciprocal_distances(const SourceTable<T>& t, const Lanes<T>& qx, const Lanes<T>& qy,
                                                        const Lanes<T>& qz, Lanes<T> (&reciprocal)[kMaxSources]) {
  if constexpr (std::is_same_v<T, float>) {
    if (t.fast_inverse_sqrt) {
      for (std::size_t s = 0; s < t.count; ++s) {
        reciprocal[s] = reciprocal_distance<true>(t, qx - t.px[s], qy - t.py[s], qz - t.pz[s]);
      }
      return;
    }
  }
  for (std::size_t s = 0; s < t.count; ++s) {
    reciprocal[s] = reciprocal_distance<false>(t, qx - t.px[s], qy - t.py[s], qz - t.pz[s]);
  }
}

// The displacement u summed over the sources at a register of points, each source's 1/r computed
// just before its share is added (and kept in `reciprocal` for a gradient that may follow); with
// kBound, the sum of the sources' bounds on ||grad u|| too. The displacement alone is short
// enough that a register's square roots and divisions all first left the core waiting for them:
// interleaved, the pass without gradients took 8 % less (BareLoop5x100k). u has the bits
// add_displacement gives whatever the pass.
template <bool kBound, bool kFast, typename T>
[[gnu::always_inline]] inline void displacement_first(const SourceTable<T>& t, const Lanes<T>& qx, const Lanes<T>& qy,
                                                      const Lanes<T>& qz, Lanes<T> (&reciprocal)[kMaxSources],
                                                      Lanes<T> (&u)[3], Lanes<T>& bound) {
  using V = Lanes<T>;
  for (std::size_t s = 0; s < t.count; ++s) {
    const V rx = qx - t.px[s], ry = qy - t.py[s], rz = qz - t.pz[s];
    const V inv = reciprocal_distance<kFast>(t, rx, ry, rz);
    if constexpr (kBound) {
      reciprocal[s] = inv;
      const V inv2 = inv * inv;
      bound = bound + lanes::fma(lanes::splat<V>(t.bound_r4[s]), inv2, lanes::splat<V>(t.bound_r2[s])) * inv2;
    }
    add_displacement(t, s, rx, ry, rz, inv, u);
  }
}

template <bool kBound, typename T>
[[gnu::always_inline]] inline void displacement_first(const SourceTable<T>& t, const Lanes<T>& qx, const Lanes<T>& qy,
                                                      const Lanes<T>& qz, Lanes<T> (&reciprocal)[kMaxSources],
                                                      Lanes<T> (&u)[3], Lanes<T>& bound) {
  if constexpr (std::is_same_v<T, float>) {
    if (t.fast_inverse_sqrt) return displacement_first<kBound, true>(t, qx, qy, qz, reciprocal, u, bound);
  }
  displacement_first<kBound, false>(t, qx, qy, qz, reciprocal, u, bound);
}

// The displacement u and gradient g summed over the sources at a register of points (each
// source's share by add_share()).
template <typename T, bool kGradient>
[[gnu::always_inline]] inline void sum_shares(const SourceTable<T>& t, const Lanes<T>& qx, const Lanes<T>& qy,
                                              const Lanes<T>& qz, const Lanes<T> (&reciprocal)[kMaxSources],
                                              Lanes<T> (&u)[3], Lanes<T> (&g)[3][3]) {
  for (std::size_t s = 0; s < t.count; ++s) {
    add_share<T, kGradient>(t, s, qx - t.px[s], qy - t.py[s], qz - t.pz[s], reciprocal[s], u, g);
  }
}

// The points of a bounded register pass that need their gradient, from registers where most
// points do not: each one's position before the move and where its normal is read and written
// (an offset from the `from` and `to` normal arrays: the model's, the journal's when writing
// aside, or a gathered block's copy). Collected until a register's worth, then computed as one
// register (in the 100k dragon's five-finger frame 8 % of the points need their gradient, but
// 30 % of the registers hold one).
template <typename T, bool kCarry>
class LaneBatch {
 public:
  static constexpr std::size_t kWidth = lanes::kCount<T>;

  void aim(const PointArrays& from, const PointArrays& to) {
    from_ = from;
    to_ = to;
  }
  std::size_t size() const { return size_; }
  // Room for a register more is kept by flushing whenever a register's worth is collected.
  void add(float x, float y, float z, std::uint32_t at) {
    x_[size_] = x;
    y_[size_] = y;
    z_[size_] = z;
    at_[size_] = at;
    ++size_;
  }

  // The first register's worth of points (all of them, padded with the last, when fewer): their
  // gradient, Jacobian and carried normal.
  void flush_register(const SourceTable<T>& t, const LaneExtremes<T>& extremes, LaneBits<T>& bad) {
    if (size_ == 0) return;
    const std::size_t m = std::min(size_, kWidth);
    alignas(64) float p[6][kWidth];
    for (std::size_t j = 0; j < kWidth; ++j) {
      const std::size_t from = std::min(j, m - 1);
      p[0][j] = x_[from];
      p[1][j] = y_[from];
      p[2][j] = z_[from];
      if constexpr (kCarry) {
        p[3][j] = from_.nx[at_[from]];
        p[4][j] = from_.ny[at_[from]];
        p[5][j] = from_.nz[at_[from]];
      }
    }
    const Lanes<T> qx = lanes::load<T>(p[0]), qy = lanes::load<T>(p[1]), qz = lanes::load<T>(p[2]);
    Lanes<T> reciprocal[kMaxSources];
    reciprocal_distances(t, qx, qy, qz, reciprocal);
    Lanes<T> u[3] = {}, g[3][3] = {};
    sum_shares<T, true>(t, qx, qy, qz, reciprocal, u, g);
    Lanes<T> n0{}, n1{}, n2{};
    if constexpr (kCarry) {
      n0 = lanes::load<T>(p[3]);
      n1 = lanes::load<T>(p[4]);
      n2 = lanes::load<T>(p[5]);
    }
    const Lanes<T> det = jacobian_and_normal<T, kCarry>(g, n0, n1, n2);
    const Lanes<T> min_det = lanes::load_values(extremes.min_det);
    lanes::store_values(extremes.min_det, det < min_det ? det : min_det);
    bad |= lanes::non_finite<T>(det);
    if constexpr (kCarry) {
      bad |= lanes::non_finite<T>(lanes::store<T>(p[3], n0)) | lanes::non_finite<T>(lanes::store<T>(p[4], n1)) |
             lanes::non_finite<T>(lanes::store<T>(p[5], n2));
      for (std::size_t j = 0; j < m; ++j) {
        to_.nx[at_[j]] = p[3][j];
        to_.ny[at_[j]] = p[4][j];
        to_.nz[at_[j]] = p[5][j];
      }
    }
    size_ -= m;
    std::copy_n(x_ + m, size_, x_);
    std::copy_n(y_ + m, size_, y_);
    std::copy_n(z_ + m, size_, z_);
    std::copy_n(at_ + m, size_, at_);
  }

  void flush(const SourceTable<T>& t, const LaneExtremes<T>& extremes, LaneBits<T>& bad) {
    while (size_ > 0) flush_register(t, extremes, bad);
  }

 private:
  PointArrays from_{}, to_{};
  std::size_t size_ = 0;
  float x_[2 * kWidth], y_[2 * kWidth], z_[2 * kWidth];
  std::uint32_t at_[2 * kWidth];
};

// A pass a register of points at a time: the sums over the sources (displacement, with
// kGradient the gradient, and with kBounded the bound on ||grad u||) stay in registers, and the
// Jacobian, the carried normal and the new position follow in the same registers.
// With kBounded, a register whose every point's bound is at most the table's skip_bound moves
// with the displacement alone and keeps its normals (counted as skipped, with their bounds); one
// where at most half the points are over it (or NaN) does the same for the others and hands
// those to the batch; any other is computed exactly, every point of it.
// Reads `from`, writes `to` (the same arrays, or the journal's when writing aside); `lane` is
// this register's first lane of the extremes and `at` the offset of its first normal from the
// batch's arrays; `valid` of its lanes are points (the rest pad a last register). ORs into
// `bad` the lanes whose Jacobian, new position or new normal is not finite. Returns how many
// points kept their normals. Always inlined into move_block: a call per register, with `bad` and
// the lane pointers spilled around it, cost the exact pass 4 % and the bounded one 5 %.
template <typename T, bool kGradient, bool kCarry, bool kBounded>
[[gnu::always_inline]] inline std::size_t move_lanes(const SourceTable<T>& t, const PointArrays& from,
                                                     const PointArrays& to, std::size_t lane, std::size_t at,
                                                     std::size_t valid, const LaneExtremes<T>& extremes,
                                                     LaneBatch<T, kCarry>& batch, LaneBits<T>& bad) {
  using V = Lanes<T>;
  constexpr std::size_t kWidth = lanes::kCount<T>;
  const V qx = lanes::load<T>(from.x), qy = lanes::load<T>(from.y), qz = lanes::load<T>(from.z);
  V reciprocal[kMaxSources];
  const auto move_to = [&](const V& ux, const V& uy, const V& uz) {
    bad |= lanes::non_finite<T>(lanes::store<T>(to.x, qx + ux)) | lanes::non_finite<T>(lanes::store<T>(to.y, qy + uy)) |
           lanes::non_finite<T>(lanes::store<T>(to.z, qz + uz));
    const V u2 = dot(ux, uy, uz, ux, uy, uz);
    const V max_squared = lanes::load_values(extremes.max_squared + lane);
    lanes::store_values(extremes.max_squared + lane, u2 > max_squared ? u2 : max_squared);
  };
  V u[3] = {};
  V g[3][3] = {};
  if constexpr (!kGradient) {
    V no_bound{};
    displacement_first<false>(t, qx, qy, qz, reciprocal, u, no_bound);
    move_to(u[0], u[1], u[2]);
    return 0;
  }
  if constexpr (kBounded) {
    // The displacement first, with the bound: most registers need nothing more.
    V bound{};
    displacement_first<true>(t, qx, qy, qz, reciprocal, u, bound);
    const LaneBits<T> within = bound <= t.skip_bound;  // NaN: not within
    const std::uint32_t valid_bits = valid >= 32 ? ~0u : (1u << valid) - 1u;
    const std::uint32_t over_bits = ~lanes::lane_bits(within) & valid_bits;
    const auto over = static_cast<std::size_t>(std::popcount(over_bits));
    if (2 * over <= valid) {
      for (std::uint32_t rest = over_bits; rest != 0; rest &= rest - 1) {
        const auto j = static_cast<std::size_t>(std::countr_zero(rest));
        batch.add(static_cast<float>(qx[j]), static_cast<float>(qy[j]), static_cast<float>(qz[j]),
                  static_cast<std::uint32_t>(at + j));
      }
      move_to(u[0], u[1], u[2]);
      if (kCarry && to.nx != from.nx) {
        std::memcpy(to.nx, from.nx, sizeof(float) * kWidth);
        std::memcpy(to.ny, from.ny, sizeof(float) * kWidth);
        std::memcpy(to.nz, from.nz, sizeof(float) * kWidth);
      }
      SkipLanes<T>& skip = *extremes.skip;
      const V floor = T(1) - bound;
      const V det_floor = within ? floor * floor * floor : lanes::splat<V>(T(1));
      const V kept_bound = within ? bound : V{};
      const V max_bound = lanes::load_values(skip.max_bound + lane);
      const V min_floor = lanes::load_values(skip.min_det_floor + lane);
      lanes::store_values(skip.max_bound + lane, kept_bound > max_bound ? kept_bound : max_bound);
      lanes::store_values(skip.min_det_floor + lane, det_floor < min_floor ? det_floor : min_floor);
      return valid - over;
    }
    // Most of the register needs its gradients: summed here from the kept reciprocals, beside
    // the displacement already summed (the exact pass's bits, which add the same shares).
    for (std::size_t s = 0; s < t.count; ++s) {
      add_gradient(t, s, V(qx - t.px[s]), V(qy - t.py[s]), V(qz - t.pz[s]), reciprocal[s], g);
    }
  } else {
    reciprocal_distances(t, qx, qy, qz, reciprocal);
    sum_shares<T, true>(t, qx, qy, qz, reciprocal, u, g);
  }
  V n0{}, n1{}, n2{};
  if constexpr (kCarry) {
    n0 = lanes::load<T>(from.nx);
    n1 = lanes::load<T>(from.ny);
    n2 = lanes::load<T>(from.nz);
  }
  const V det = jacobian_and_normal<T, kCarry>(g, n0, n1, n2);
  if constexpr (kCarry) {
    bad |= lanes::non_finite<T>(lanes::store<T>(to.nx, n0)) | lanes::non_finite<T>(lanes::store<T>(to.ny, n1)) |
           lanes::non_finite<T>(lanes::store<T>(to.nz, n2));
  }
  const V min_det = lanes::load_values(extremes.min_det + lane);
  lanes::store_values(extremes.min_det + lane, det < min_det ? det : min_det);
  bad |= lanes::non_finite<T>(det);
  move_to(u[0], u[1], u[2]);
  return 0;
}

// A block's n points (move_lanes), from one set of arrays to another (or the same: in place).
// A last partial register works on a copy padded with its last point, whose extremes are that
// point's own, so they change nothing. `at` is the block's first normal's offset from the
// batch's arrays; the batch is computed whenever it holds a register's worth (after a padded
// register is copied back, never before). Returns non-zero when a Jacobian, a new position or a
// new normal was not finite; adds the points that kept their normals to `skipped`.
template <typename T, bool kGradient, bool kCarry, bool kBounded>
std::uint32_t move_block(const SourceTable<T>& t, std::size_t n, const PointArrays& from, const PointArrays& to,
                         std::size_t at, const LaneExtremes<T>& extremes, LaneBatch<T, kCarry>& batch,
                         std::size_t& skipped) {
  constexpr std::size_t kWidth = lanes::kCount<T>;
  LaneBits<T> bad{};
  std::size_t k = 0;
  for (; k + kWidth <= n; k += kWidth) {
    skipped +=
        move_lanes<T, kGradient, kCarry, kBounded>(t, from.at(k), to.at(k), k, at + k, kWidth, extremes, batch, bad);
    if (batch.size() >= kWidth) batch.flush_register(t, extremes, bad);
  }
  if (k < n) {
    alignas(64) float copy[6][kWidth];
    float* const in[6] = {from.x, from.y, from.z, from.nx, from.ny, from.nz};
    float* const out[6] = {to.x, to.y, to.z, to.nx, to.ny, to.nz};
    const int arrays = kCarry ? 6 : 3;
    for (int a = 0; a < arrays; ++a) {
      for (std::size_t j = 0; j < kWidth; ++j) copy[a][j] = in[a][std::min(k + j, n - 1)];
    }
    const PointArrays padded{copy[0], copy[1], copy[2], copy[3], copy[4], copy[5]};
    skipped += move_lanes<T, kGradient, kCarry, kBounded>(t, padded, padded, k, at + k, n - k, extremes, batch, bad);
    for (int a = 0; a < arrays; ++a) std::copy_n(copy[a], n - k, out[a] + k);
    if (batch.size() >= kWidth) batch.flush_register(t, extremes, bad);
  }
  return lanes::any(bad) ? 1u : 0u;
}

}  // namespace

// Copies n floats with non-temporal stores where the target has them (plain stores elsewhere).
// For the journal of a global pass: written once a frame and read back only when a frame is
// undone, so written around the caches it neither evicts the model's arrays nor first reads
// every line it overwrites (at 437,645 points, 10 MB a frame). The caller fences (finish_streaming)
// before anyone else may read the copy.
void stream_copy(float* __restrict dst, const float* __restrict src, std::size_t n) noexcept {
  std::size_t k = 0;
#if defined(__AVX512F__)
  constexpr std::size_t kWidth = 16;
  auto store = [](float* d, const float* s) { _mm512_stream_ps(d, _mm512_loadu_ps(s)); };
#elif defined(__AVX__)
  constexpr std::size_t kWidth = 8;
  auto store = [](float* d, const float* s) { _mm256_stream_ps(d, _mm256_loadu_ps(s)); };
#elif defined(__SSE__)
  constexpr std::size_t kWidth = 4;
  auto store = [](float* d, const float* s) { _mm_stream_ps(d, _mm_loadu_ps(s)); };
#endif
#if defined(__SSE__)
  constexpr std::uintptr_t kAlign = kWidth * sizeof(float);
  for (; k < n && reinterpret_cast<std::uintptr_t>(dst + k) % kAlign != 0; ++k) dst[k] = src[k];
  for (; k + kWidth <= n; k += kWidth) store(dst + k, src + k);
#endif
  for (; k < n; ++k) dst[k] = src[k];
}

// Orders this thread's non-temporal stores before whatever it does next (the worker's "done",
// the caller's return): they are weakly ordered otherwise.
void finish_streaming() noexcept {
#if defined(__SSE__)
  _mm_sfence();
#endif
}

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
  // Whether a global pass may write its new values into the journal's arrays and then trade
  // them for the model's (write_aside()): the journal holds a whole model's worth.
  bool can_write_aside(const PointModel& model, bool normals) const noexcept {
    return j.x_.size() == model.size() && (!normals || (j.normals_ && j.nx_.size() == model.size()));
  }
  // Where a pass writing aside puts point `at`'s new values.
  PointArrays aside(std::size_t at, bool normals) const noexcept {
    return {j.x_.data() + at,
            j.y_.data() + at,
            j.z_.data() + at,
            normals ? j.nx_.data() + at : nullptr,
            normals ? j.ny_.data() + at : nullptr,
            normals ? j.nz_.data() + at : nullptr};
  }
  // After a pass that wrote aside: the model takes the new values and the journal keeps the
  // model's old arrays, which are the old values of every point, as record() would have left them.
  void write_aside(PointModel& model, bool normals) const noexcept {
    model.x.swap(j.x_);
    model.y.swap(j.y_);
    model.z.swap(j.z_);
    if (normals) {
      model.nx.swap(j.nx_);
      model.ny.swap(j.ny_);
      model.nz.swap(j.nz_);
    }
    j.contiguous_ = true;
    j.recorded_normals_ = normals;
    j.count_ = model.size();
  }
  template <bool kContiguous, typename IndexOf>
  void record(IndexOf index_of, std::size_t begin, std::size_t n, const float* x, const float* y, const float* z,
              const float* nx, const float* ny, const float* nz) const noexcept {
    const std::size_t at = begin;
    if (at + n > j.count_) return;  // begin_pass found no room for the pass
    if constexpr (!kContiguous) {
      for (std::size_t k = 0; k < n; ++k) j.index_[at + k] = static_cast<std::uint32_t>(index_of(begin + k));
    }
    // A global pass's journal is as large as the model: written around the caches. A region's
    // is small and stays in them.
    const auto copy = [](float* dst, const float* src, std::size_t count) {
      if constexpr (kContiguous) {
        stream_copy(dst, src, count);
      } else {
        std::memcpy(dst, src, count * sizeof(float));
      }
    };
    copy(j.x_.data() + at, x, n);
    copy(j.y_.data() + at, y, n);
    copy(j.z_.data() + at, z, n);
    if (j.normals_ && nx) {
      copy(j.nx_.data() + at, nx, n);
      copy(j.ny_.data() + at, ny, n);
      copy(j.nz_.data() + at, nz, n);
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

// Whether a block's n points are n consecutive points of the model, in order.
template <typename IndexOf>
bool consecutive(IndexOf index_of, std::size_t begin, std::size_t n) noexcept {
  const std::size_t first = index_of(begin);
  for (std::size_t k = 1; k < n; ++k) {
    if (index_of(begin + k) != first + k) return false;
  }
  return true;
}

// Where a block's three attributes are worked on: the model's arrays from `begin` in a
// contiguous pass, the block's copy (gathered here) otherwise.
template <bool kContiguous, typename IndexOf>
std::array<float*, 3> block_arrays(IndexOf index_of, std::size_t begin, std::size_t n, std::vector<float>& a,
                                   std::vector<float>& b, std::vector<float>& c, float* ka, float* kb, float* kc) {
  if constexpr (kContiguous) {
    return {a.data() + begin, b.data() + begin, c.data() + begin};
  } else {
    copy_indexed<true>(index_of, begin, n, a, b, c, ka, kb, kc);
    return {ka, kb, kc};
  }
}

// The extremes of part of a pass, reduced across parts exactly (max and min do not depend on
// the order).
template <typename T>
struct PassExtremes {
  T max_squared = T(0);
  T min_det = T(1);
  std::uint32_t bad = 0;
  SkipStats skips;
};

// Each block: record the old positions (and normals) in the journal, then move it a register at
// a time (move_block). When every point moves (kContiguous), or the block's points are
// consecutive in the model, the block works in place on the model's arrays; otherwise on a
// gathered copy, scattered back at the end. The extremes are kept
// per block lane and reduced once at the end: max and min are exact whatever the order.
// Covers the pass's points first .. last - 1 (first a multiple of kBlock).
// With kBounded, the gradient is computed only where its bound exceeds the table's skip_bound.
// With `aside` (a global pass, apply_typed decides), the new values go to the journal's arrays
// instead of over the old ones, and nothing is copied into the journal: the caller then trades
// the arrays (JournalWriter::write_aside).
template <typename T, bool kGradient, bool kCarry, bool kContiguous, bool kBounded, typename IndexOf>
PassExtremes<T> apply_range(PointModel& model, const SourceTable<T>& t, std::size_t first, std::size_t last,
                            IndexOf index_of, UndoJournal* journal, bool aside) noexcept {
  static_assert(kGradient || !kCarry, "carrying normals needs the gradient");
  static_assert(kGradient || !kBounded, "only a gradient can be bounded");
  SkipStats skips;
  SkipLanes<T> skip_lanes;
  alignas(64) float gx[kBlock], gy[kBlock], gz[kBlock];     // gathered positions
  alignas(64) float gnx[kBlock], gny[kBlock], gnz[kBlock];  // gathered normals
  alignas(64) T lane_max_squared[kBlock];
  alignas(64) T lane_min_det[kBlock];
  for (std::size_t k = 0; k < kBlock; ++k) {
    lane_max_squared[k] = T(0);
    lane_min_det[k] = T(1);
  }
  std::uint32_t bad = 0;
  const LaneExtremes<T> extremes{lane_min_det, lane_max_squared, &skip_lanes};
  // A contiguous pass batches across its blocks, by point index; a gathered one within each
  // block, into the block's copy.
  LaneBatch<T, kCarry> lane_batch;
  LaneBits<T> batch_bad{};
  const PointArrays model_arrays{model.x.data(),  model.y.data(),  model.z.data(),
                                 model.nx.data(), model.ny.data(), model.nz.data()};
  const PointArrays copy{gx, gy, gz, gnx, gny, gnz};
  if constexpr (kContiguous) {
    lane_batch.aim(model_arrays, aside ? JournalWriter{*journal}.aside(0, kCarry) : model_arrays);
  } else {
    lane_batch.aim(copy, copy);
  }
  for (std::size_t begin = first; begin < last; begin += kBlock) {
    const std::size_t n = std::min(kBlock, last - begin);
    // A gathered pass's block whose points are consecutive in the model (a region holding
    // much of the model, or one of a model stored in Z order) is worked on in place, like a
    // contiguous pass's: a gather and a scatter the less, the same arithmetic on the same values.
    if constexpr (!kContiguous) {
      if (consecutive(index_of, begin, n)) {
        const std::size_t at = index_of(begin);
        const PointArrays run = model_arrays.at(at);
        const PointArrays in_place{
            run.x, run.y, run.z, kCarry ? run.nx : nullptr, kCarry ? run.ny : nullptr, kCarry ? run.nz : nullptr};
        if (journal) {
          JournalWriter{*journal}.record<false>(index_of, begin, n, in_place.x, in_place.y, in_place.z, in_place.nx,
                                                in_place.ny, in_place.nz);
        }
        lane_batch.aim(in_place, in_place);
        bad |= move_block<T, kGradient, kCarry, kBounded>(t, n, in_place, in_place, 0, extremes, lane_batch,
                                                          skips.skipped);
        lane_batch.flush(t, extremes, batch_bad);
        lane_batch.aim(copy, copy);
        continue;
      }
    }
    const auto [x, y, z] = block_arrays<kContiguous>(index_of, begin, n, model.x, model.y, model.z, gx, gy, gz);
    float *nx = nullptr, *ny = nullptr, *nz = nullptr;
    if constexpr (kCarry) {
      const std::array<float*, 3> at =
          block_arrays<kContiguous>(index_of, begin, n, model.nx, model.ny, model.nz, gnx, gny, gnz);
      nx = at[0];
      ny = at[1];
      nz = at[2];
    }
    if (journal && !aside) JournalWriter{*journal}.record<kContiguous>(index_of, begin, n, x, y, z, nx, ny, nz);
    const PointArrays in_place{x, y, z, nx, ny, nz};
    const PointArrays to = aside ? JournalWriter{*journal}.aside(begin, kCarry) : in_place;
    bad |= move_block<T, kGradient, kCarry, kBounded>(t, n, in_place, to, kContiguous ? begin : 0, extremes, lane_batch,
                                                      skips.skipped);
    if constexpr (!kContiguous) {
      lane_batch.flush(t, extremes, batch_bad);
      copy_indexed<false>(index_of, begin, n, model.x, model.y, model.z, gx, gy, gz);
      if constexpr (kCarry) copy_indexed<false>(index_of, begin, n, model.nx, model.ny, model.nz, gnx, gny, gnz);
    }
  }
  lane_batch.flush(t, extremes, batch_bad);
  for (std::size_t j = 0; j < lanes::kCount<T>; ++j) bad |= static_cast<std::uint32_t>(batch_bad[j] != 0);
  if constexpr (kContiguous) {
    if (journal && !aside) finish_streaming();
  }
  PassExtremes<T> e;
  e.bad = bad;
  if constexpr (kBounded) skip_lanes.add_to(skips);
  e.skips = skips;
  for (std::size_t k = 0; k < kBlock; ++k) {
    e.max_squared = lane_max_squared[k] > e.max_squared ? lane_max_squared[k] : e.max_squared;
    e.min_det = lane_min_det[k] < e.min_det ? lane_min_det[k] : e.min_det;
  }
  return e;
}

// Below this many points a pass runs on the caller alone: waking the worker costs microseconds.
constexpr std::size_t kMinSplitPoints = 16384;
// A shared pass is cut into parts of at most this many points (about 40 us of a five-finger
// frame), so that a worker kept off its core holds the frame for at most that, and at most
// kMaxPassParts of them.
constexpr std::size_t kPartPoints = 8192;
constexpr std::size_t kMaxPassParts = 64;
// The smallest part: four blocks.
constexpr std::size_t kMinPartPoints = 4 * kBlock;

// Where a shared pass's parts begin (and, last, `count`): parts of kPartPoints while the rest
// is large (larger on a model of over 320,000 points, so that 40 of them cover it), then each a
// quarter of what is left, down to kMinPartPoints. The threads then finish within a small part
// of each other: with parts of one size, the thread that took the last one finished a whole
// part after the other (13 parts at 100,000 points: 7 against 6, 8 % of the pass). Every bound
// is a multiple of kBlock, as the blocks of a pass on one thread fall.
std::size_t cut_into_parts(std::size_t count, std::array<std::size_t, kMaxPassParts + 1>& bounds) noexcept {
  const std::size_t largest = std::max(kPartPoints, (count / 40 + kBlock - 1) / kBlock * kBlock);
  std::size_t parts = 0, at = 0;
  bounds[0] = 0;
  while (at < count && parts + 1 < kMaxPassParts) {
    const std::size_t rest = count - at;
    std::size_t size = std::clamp(rest / 4, kMinPartPoints, largest);
    size = (size + kBlock - 1) / kBlock * kBlock;
    at = std::min(count, at + size);
    bounds[++parts] = at;
  }
  if (at < count) bounds[++parts] = count;  // the part budget spent: the rest in one
  return parts;
}

// A pass over `count` points, shared with the worker in parts cut at block boundaries when
// there is one and the pass is large enough.
template <typename T, bool kGradient, bool kCarry, bool kContiguous, bool kBounded, typename IndexOf>
FieldResult apply_typed(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                        UndoJournal* journal, FieldWorker* worker) {
  if (journal) JournalWriter{*journal}.begin_pass(kContiguous, kCarry, count);
  // A fused global pass writes its new values beside the old ones, in the journal's arrays, and
  // the two sets change places at the end: the journal then holds the old values without a copy
  // (a third of a global frame's memory traffic).
  const bool aside = kContiguous && journal && JournalWriter{*journal}.can_write_aside(model, kCarry);
  PassExtremes<T> e;
  if (!worker || count < kMinSplitPoints) {
    e = apply_range<T, kGradient, kCarry, kContiguous, kBounded>(model, t, 0, count, index_of, journal, aside);
  } else {
    struct Parts {
      PointModel& model;
      const SourceTable<T>& table;
      IndexOf index_of;
      UndoJournal* journal;
      bool aside;
      std::array<std::size_t, kMaxPassParts + 1> bounds;
      PassExtremes<T> part[kMaxPassParts];
    } parts{model, t, index_of, journal, aside, {}, {}};
    const std::size_t part_count = cut_into_parts(count, parts.bounds);
    worker->run_parts(
        [](void* context, std::size_t part) noexcept {
          Parts& p = *static_cast<Parts*>(context);
          p.part[part] = apply_range<T, kGradient, kCarry, kContiguous, kBounded>(
              p.model, p.table, p.bounds[part], p.bounds[part + 1], p.index_of, p.journal, p.aside);
        },
        &parts, part_count);
    // Max, min and integer sums: exact in any order, so the same whichever thread ran a part.
    for (std::size_t k = 0; k < part_count; ++k) {
      const PassExtremes<T>& x = parts.part[k];
      e.max_squared = std::max(e.max_squared, x.max_squared);
      e.min_det = std::min(e.min_det, x.min_det);
      e.bad |= x.bad;
      e.skips.skipped += x.skips.skipped;
      e.skips.max_skipped_bound = std::max(e.skips.max_skipped_bound, x.skips.max_skipped_bound);
      e.skips.min_det_floor = std::min(e.skips.min_det_floor, x.skips.min_det_floor);
    }
  }
  if (aside) JournalWriter{*journal}.write_aside(model, kCarry);
  FieldResult result;
  result.finite = e.bad == 0 && std::isfinite(static_cast<double>(e.max_squared));
  result.max_displacement = std::sqrt(static_cast<double>(e.max_squared));
  result.min_jacobian = std::min(static_cast<double>(e.min_det), e.skips.min_det_floor);
  result.gradients_skipped = e.skips.skipped;
  result.max_skipped_bound = e.skips.max_skipped_bound;
  return result;
}

// The loop variants as compile-time choices, so none of them tests a flag per point.
template <typename T, bool kContiguous, typename IndexOf>
FieldResult apply_variant(PointModel& model, const SourceTable<T>& t, std::size_t count, IndexOf index_of,
                          bool carry_normals, bool jacobian, UndoJournal* journal, FieldWorker* worker) {
  const bool bounded = t.skip_bound > T(0);
  if (carry_normals && bounded) {
    return apply_typed<T, true, true, kContiguous, true>(model, t, count, index_of, journal, worker);
  }
  if (carry_normals) return apply_typed<T, true, true, kContiguous, false>(model, t, count, index_of, journal, worker);
  if (jacobian && bounded) {
    return apply_typed<T, true, false, kContiguous, true>(model, t, count, index_of, journal, worker);
  }
  if (jacobian) return apply_typed<T, true, false, kContiguous, false>(model, t, count, index_of, journal, worker);
  return apply_typed<T, false, false, kContiguous, false>(model, t, count, index_of, journal, worker);
}

template <typename T>
FieldResult apply_in(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                     std::span<const std::uint32_t> indices, bool all_points, bool carry_normals, bool jacobian,
                     const FieldOptions& options, UndoJournal* journal, FieldWorker* worker) {
  SourceTable<T> table = make_table<T>(kernel, sources);
  table.skip_bound = static_cast<T>(options.normal_skip_bound);
  table.fast_inverse_sqrt = options.fast_inverse_sqrt;
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

double normal_bound_angle(double gradient_bound) noexcept {
  // ||F^-T - I|| <= b / (1 - b) by the Neumann series of (I + grad u)^-1, and a vector moved
  // by at most d (< 1) of its length turns by at most asin(d).
  if (!(gradient_bound > 0.0)) return 0.0;
  return std::asin(std::min(1.0, gradient_bound / (1.0 - gradient_bound)));
}

FieldResult apply_displacements(PointModel& model, const Kernel& kernel, std::span<const SourceForce> sources,
                                std::span<const std::uint32_t> indices, bool all_points, const FieldOptions& options,
                                bool jacobian, UndoJournal* journal, FieldWorker* worker) noexcept {
  if (journal) journal->clear();
  if (sources.empty()) return {};
  const bool normals = options.carry_normals && model.has_normals();
  if (options.precision == Precision::kDouble) {
    return apply_in<double>(model, kernel, sources, indices, all_points, normals, jacobian, options, journal, worker);
  }
  return apply_in<float>(model, kernel, sources, indices, all_points, normals, jacobian, options, journal, worker);
}

}  // namespace sculpt::deform
