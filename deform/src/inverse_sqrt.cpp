#include "sculpt/deform/inverse_sqrt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
// GCC 12 reports a false -Wmaybe-uninitialized for _mm512_rsqrt14_ps, whose unmasked form passes
// _mm512_undefined_ps() as the (unused) merge source (GCC bug 105593); nothing is read
// uninitialised.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif

namespace sculpt::deform {
namespace {

// The estimate is used for normal positive floats only (a clear sign bit, an exponent field
// neither 0 nor all ones); the rest get the exact value. They need a point at a source's very
// position with no regularisation, or a value that is not finite, so the fix-up all but never runs.
inline bool outside_estimate(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const std::uint32_t exponent = (bits >> 23) & 0xffu;
  return (bits >> 31) != 0 || exponent == 0 || exponent == 0xffu;
}

template <std::size_t kLanes>
void fix_outside(const float* x, float* out) {
  for (std::size_t k = 0; k < kLanes; ++k) {
    if (outside_estimate(x[k])) out[k] = 1.0f / std::sqrt(x[k]);
  }
}

// One vector of lanes, in place: y = estimate, then one Newton step y (3/2 - (x/2) y^2). Lanes
// outside the estimate's range are redone from a copy of the input.
#if defined(__AVX512F__)
constexpr std::size_t kLanes = 16;
inline void estimate_lanes(float* values) {
  const __m512 v = _mm512_loadu_ps(values);
  const __m512 y = _mm512_rsqrt14_ps(v);
  const __m512 half_xy = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), v), y);
  _mm512_storeu_ps(values, _mm512_mul_ps(y, _mm512_fnmadd_ps(half_xy, y, _mm512_set1_ps(1.5f))));
  // Read as signed integers, the normal positive floats are exactly 0x00800000 .. 0x7f7fffff.
  const __m512i bits = _mm512_castps_si512(v);
  const __mmask16 usable = _mm512_cmpge_epi32_mask(bits, _mm512_set1_epi32(0x00800000)) &
                           _mm512_cmple_epi32_mask(bits, _mm512_set1_epi32(0x7f7fffff));
  if (usable != 0xffff) {
    alignas(64) float x[kLanes];
    _mm512_store_ps(x, v);
    fix_outside<kLanes>(x, values);
  }
}
#elif defined(__SSE2__)
constexpr std::size_t kLanes = 4;
inline void estimate_lanes(float* values) {
  const __m128 v = _mm_loadu_ps(values);
  const __m128 y = _mm_rsqrt_ps(v);
  const __m128 half_xy = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(0.5f), v), y);
  _mm_storeu_ps(values, _mm_mul_ps(y, _mm_sub_ps(_mm_set1_ps(1.5f), _mm_mul_ps(half_xy, y))));
  const __m128 usable =
      _mm_and_ps(_mm_cmpge_ps(v, _mm_set1_ps(0x1p-126f)), _mm_cmple_ps(v, _mm_set1_ps(0x1.fffffep127f)));
  if (_mm_movemask_ps(usable) != 0xf) {
    alignas(16) float x[kLanes];
    _mm_store_ps(x, v);
    fix_outside<kLanes>(x, values);
  }
}
#else
constexpr std::size_t kLanes = 1;
inline void estimate_lanes(float* values) { values[0] = 1.0f / std::sqrt(values[0]); }
#endif

}  // namespace

// Error: one Newton step for f(y) = 1/y^2 - x from an estimate with relative error e leaves
// 3/2 e^2 + O(e^3). The estimate's e is at most 2^-14 (rsqrt14: 2^-27.4 after the step) or
// 1.5 * 2^-12 (SSE rsqrt, also used on AVX2 machines: 2^-22.2 after it). The step's four roundings add at most about 4 * 2^-24 =
// 2^-22. Both sums stay below kInverseSqrtEstimateError = 2^-21.
void inverse_sqrt_estimate(float* values, std::size_t n) noexcept {
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) estimate_lanes(values + k);
  if (k < n) {  // the last few, padded to a whole vector, so that every value is the estimate
    float padded[kLanes];
    std::fill(padded, padded + kLanes, 1.0f);
    std::copy(values + k, values + n, padded);
    estimate_lanes(padded);
    std::copy(padded, padded + (n - k), values + k);
  }
}

const char* inverse_sqrt_estimate_kind() noexcept {
#if defined(__AVX512F__)
  return "AVX-512 rsqrt14";
#elif defined(__SSE2__)
  return "SSE rsqrt";
#else
  return "none";
#endif
}

}  // namespace sculpt::deform
