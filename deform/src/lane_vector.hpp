#pragma once
// One register of lanes (GCC vector values: 16 floats or 8 doubles with AVX-512, half that with
// AVX, a quarter with SSE), for loops that keep their running sums in registers across an inner
// loop, where the auto-vectoriser would keep them in memory. Every lane operation is the scalar
// IEEE operation lane by lane (fused multiply-add and square root correctly rounded, as
// std::fma and std::sqrt), so a lane computes exactly what the scalar code computes.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#if defined(__SSE2__)
// GCC 12 reports a false -Wmaybe-uninitialized (and -Wuninitialized) inside the unmasked AVX-512
// square roots and estimates, which pass _mm512_undefined_ps() as the unused merge source (GCC bug 105593).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif

namespace sculpt::deform::lanes {

// The target's widest register: a wider GCC vector would be split into several anyway, and
// passing it by value would use an ABI GCC warns about (-Wpsabi).
#if defined(__AVX512F__)
inline constexpr std::size_t kBytes = 64;
#elif defined(__AVX__)
inline constexpr std::size_t kBytes = 32;
#else
inline constexpr std::size_t kBytes = 16;
#endif

template <typename T>
struct LaneTypes;

template <>
struct LaneTypes<float> {
  static constexpr std::size_t kCount = kBytes / sizeof(float);
  using Value = float __attribute__((vector_size(kBytes)));
  using Floats = Value;                                            // the same lanes as stored floats
  using Bits = std::int32_t __attribute__((vector_size(kBytes)));  // a comparison's result
};

template <>
struct LaneTypes<double> {
  static constexpr std::size_t kCount = kBytes / sizeof(double);
  using Value = double __attribute__((vector_size(kBytes)));
  using Floats = float __attribute__((vector_size(kBytes / 2)));
  using Bits = std::int64_t __attribute__((vector_size(kBytes)));
};

template <typename T>
inline constexpr std::size_t kCount = LaneTypes<T>::kCount;
template <typename T>
using Value = typename LaneTypes<T>::Value;

// kCount<T> floats from p (any alignment), in T.
template <typename T>
inline Value<T> load(const float* p) noexcept {
  typename LaneTypes<T>::Floats f;
  std::memcpy(&f, p, sizeof f);
  if constexpr (std::is_same_v<T, float>) {
    return f;
  } else {
    return __builtin_convertvector(f, Value<T>);
  }
}

// Stores the lanes rounded to float (exact for T = float); returns what was stored, in T (a
// double too large for a float comes back infinite).
template <typename T>
inline Value<T> store(float* p, Value<T> v) noexcept {
  if constexpr (std::is_same_v<T, float>) {
    std::memcpy(p, &v, sizeof v);
    return v;
  } else {
    const auto f = __builtin_convertvector(v, typename LaneTypes<T>::Floats);
    std::memcpy(p, &f, sizeof f);
    return __builtin_convertvector(f, Value<T>);
  }
}

template <typename T>
inline Value<T> load_values(const T* p) noexcept {
  Value<T> v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <typename T>
inline void store_values(T* p, Value<T> v) noexcept {
  std::memcpy(p, &v, sizeof v);
}

// Every lane c: c - 0 is c exactly (a signed zero and NaN included), and compiles to one
// broadcast; a loop over the lanes compiled to sixteen masked ones.
template <typename V, typename T>
inline V splat(T c) noexcept {
  return c - V{};
}

// The target's instruction where it has one: a lane loop is turned into one instruction only
// while GCC's vectoriser judges it worth it, and inlined into a large function it was not (it
// emitted sixteen scalar fused multiply-adds with the extractions between them).
template <typename V>
inline V fma(V a, V b, V c) noexcept {
  using T = std::remove_cvref_t<decltype(a[0])>;
#if defined(__AVX512F__)
  if constexpr (sizeof(V) == 64 && std::is_same_v<T, float>) return _mm512_fmadd_ps(a, b, c);
  if constexpr (sizeof(V) == 64 && std::is_same_v<T, double>) return _mm512_fmadd_pd(a, b, c);
#endif
#if defined(__FMA__)
  if constexpr (sizeof(V) == 32 && std::is_same_v<T, float>) return _mm256_fmadd_ps(a, b, c);
  if constexpr (sizeof(V) == 32 && std::is_same_v<T, double>) return _mm256_fmadd_pd(a, b, c);
  if constexpr (sizeof(V) == 16 && std::is_same_v<T, float>) return _mm_fmadd_ps(a, b, c);
  if constexpr (sizeof(V) == 16 && std::is_same_v<T, double>) return _mm_fmadd_pd(a, b, c);
#endif
  V r{};  // initialised: GCC 12 -O1 without FMA (the TSan build) warned it may be read uninitialised
  for (std::size_t j = 0; j < sizeof(V) / sizeof(T); ++j) r[j] = std::fma(a[j], b[j], c[j]);
  return r;
}

template <typename V>
inline V sqrt(V a) noexcept {
  using T = std::remove_cvref_t<decltype(a[0])>;
#if defined(__AVX512F__)
  if constexpr (sizeof(V) == 64 && std::is_same_v<T, float>) return _mm512_sqrt_ps(a);
  if constexpr (sizeof(V) == 64 && std::is_same_v<T, double>) return _mm512_sqrt_pd(a);
#endif
#if defined(__AVX__)
  if constexpr (sizeof(V) == 32 && std::is_same_v<T, float>) return _mm256_sqrt_ps(a);
  if constexpr (sizeof(V) == 32 && std::is_same_v<T, double>) return _mm256_sqrt_pd(a);
#endif
#if defined(__SSE2__)
  if constexpr (sizeof(V) == 16 && std::is_same_v<T, float>) return _mm_sqrt_ps(a);
  if constexpr (sizeof(V) == 16 && std::is_same_v<T, double>) return _mm_sqrt_pd(a);
#endif
  V r{};
  for (std::size_t j = 0; j < sizeof(V) / sizeof(T); ++j) r[j] = std::sqrt(a[j]);
  return r;
}

// Whether any lane of a comparison's result (all ones or zero per lane) is set: one OR over
// the register's 64-bit words, with no branch per lane.
template <typename Bits>
inline bool any(Bits mask) noexcept {
  std::uint64_t words[sizeof(Bits) / 8];
  std::memcpy(words, &mask, sizeof words);
  std::uint64_t set = 0;
  for (const std::uint64_t w : words) set |= w;
  return set != 0;
}

// The lanes of a comparison's result (all ones or zero per lane) as bits, lane j in bit j: one
// instruction where the target has it. A loop reading the lanes one by one compiled to an
// extraction, a test and an add with carry per lane (the bounded pass's count of points over
// its bound, about a tenth of that pass).
template <typename Bits>
inline std::uint32_t lane_bits(Bits mask) noexcept {
  using L = std::remove_cvref_t<decltype(mask[0])>;
  constexpr std::size_t kLanes = sizeof(Bits) / sizeof(L);
#if defined(__AVX512F__)
  if constexpr (sizeof(Bits) == 64 && sizeof(L) == 4) {
    const auto m = reinterpret_cast<__m512i>(mask);
    return _mm512_test_epi32_mask(m, m);
  }
  if constexpr (sizeof(Bits) == 64 && sizeof(L) == 8) {
    const auto m = reinterpret_cast<__m512i>(mask);
    return _mm512_test_epi64_mask(m, m);
  }
#endif
#if defined(__AVX__)
  if constexpr (sizeof(Bits) == 32 && sizeof(L) == 4) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(reinterpret_cast<__m256>(mask)));
  }
  if constexpr (sizeof(Bits) == 32 && sizeof(L) == 8) {
    return static_cast<std::uint32_t>(_mm256_movemask_pd(reinterpret_cast<__m256d>(mask)));
  }
#endif
#if defined(__SSE2__)
  if constexpr (sizeof(Bits) == 16 && sizeof(L) == 4) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(reinterpret_cast<__m128>(mask)));
  }
  if constexpr (sizeof(Bits) == 16 && sizeof(L) == 8) {
    return static_cast<std::uint32_t>(_mm_movemask_pd(reinterpret_cast<__m128d>(mask)));
  }
#endif
  std::uint32_t bits = 0;
  for (std::size_t j = 0; j < kLanes; ++j) bits |= static_cast<std::uint32_t>(mask[j] != 0) << j;
  return bits;
}

// 1/sqrt(x) in every lane from the processor's reciprocal square root estimate y, refined by one
// Newton step y (3/2 - (x/2) y^2) (FieldOptions::fast_inverse_sqrt; inverse_sqrt.cpp derives the
// error bound). A lane that is not a normal positive float gets the exact 1 / sqrt(x) instead:
// the estimate is not reliable there, and such a lane all but never occurs (a point at a source
// with no regularisation, or a value that is not finite), so it is a branch, not a select.
inline Value<float> inverse_sqrt_estimate(Value<float> x) noexcept {
  using V = Value<float>;
  V y;
#if defined(__AVX512F__)
  y = _mm512_rsqrt14_ps(x);
#elif defined(__AVX__)
  y = _mm256_rsqrt_ps(x);
#elif defined(__SSE__)
  y = _mm_rsqrt_ps(x);
#else
  for (std::size_t j = 0; j < kCount<float>; ++j) y[j] = 1.0f / std::sqrt(x[j]);
  return y;
#endif
  const V half_xy = (splat<V>(0.5f) * x) * y;
#if defined(__FMA__) || defined(__AVX512F__)
  V refined = y * fma(-half_xy, y, splat<V>(1.5f));
#else
  V refined = y * (splat<V>(1.5f) - half_xy * y);
#endif
  // Read as signed integers, the normal positive floats are exactly 0x00800000 .. 0x7f7fffff.
  typename LaneTypes<float>::Bits bits;
  std::memcpy(&bits, &x, sizeof bits);
  const auto outside = (bits < 0x00800000) | (bits > 0x7f7fffff);
  if (any(outside)) {
    for (std::size_t j = 0; j < kCount<float>; ++j) {
      if (outside[j] != 0) refined[j] = 1.0f / std::sqrt(x[j]);
    }
  }
  return refined;
}

// Lanes all of whose exponent bits are set (infinite or NaN): all ones there, zero elsewhere.
template <typename T>
inline typename LaneTypes<T>::Bits non_finite(Value<T> v) noexcept {
  using Bits = typename LaneTypes<T>::Bits;
  constexpr auto kExponent = static_cast<std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>>(
      sizeof(T) == 4 ? 0x7f800000ll : 0x7ff0000000000000ll);
  Bits bits;
  std::memcpy(&bits, &v, sizeof bits);
  return (bits & kExponent) == kExponent;
}

}  // namespace sculpt::deform::lanes
