#pragma once
// 1/sqrt(x) for many floats from the processor's reciprocal square root estimate, refined by one
// Newton step: the named approximation FieldOptions::fast_inverse_sqrt uses in place of a square
// root and a division per point and source.

#include <cstddef>

namespace sculpt::deform {

/// The largest relative error of inverse_sqrt_estimate() against the exact 1/sqrt(x), for x
/// a normal positive float (2^-21, about 4 float ulps; README's physics notes derive it).
inline constexpr double kInverseSqrtEstimateError = 0x1p-21;

/// Replaces each of values[0 .. n) by 1/sqrt(x), within kInverseSqrtEstimateError where x is a
/// normal positive float; where x is 0, subnormal, infinite, negative or NaN, by the exact
/// 1.0f / std::sqrt(x) (the estimate is not reliable there). No allocation.
void inverse_sqrt_estimate(float* values, std::size_t n) noexcept;

/// The estimate this build uses: "AVX-512 rsqrt14", "AVX rsqrt", "SSE rsqrt", or "none" where
/// the target has none (every value is then the exact 1.0f / std::sqrt(x)).
const char* inverse_sqrt_estimate_kind() noexcept;

}  // namespace sculpt::deform
