#include "sculpt/deform/inverse_sqrt.hpp"

#include <algorithm>

#include "lane_vector.hpp"

namespace sculpt::deform {

// Error: one Newton step for f(y) = 1/y^2 - x from an estimate with relative error e leaves
// 3/2 e^2 + O(e^3). The estimate's e is at most 2^-14 (rsqrt14: 2^-27.4 after the step) or
// 1.5 * 2^-12 (SSE's and AVX's rsqrt: 2^-22.2 after it). The step's four roundings add at most
// about 4 * 2^-24 = 2^-22. Both sums stay below kInverseSqrtEstimateError = 2^-21. The estimate
// itself is lanes::inverse_sqrt_estimate(), which the register pass calls on its registers.
void inverse_sqrt_estimate(float* values, std::size_t n) noexcept {
  constexpr std::size_t kLanes = lanes::kCount<float>;
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
    lanes::store<float>(values + k, lanes::inverse_sqrt_estimate(lanes::load<float>(values + k)));
  }
  if (k < n) {  // the last few, padded to a whole register, so that every value is the estimate
    float padded[kLanes];
    std::fill(padded, padded + kLanes, 1.0f);
    std::copy(values + k, values + n, padded);
    lanes::store<float>(padded, lanes::inverse_sqrt_estimate(lanes::load<float>(padded)));
    std::copy(padded, padded + (n - k), values + k);
  }
}

const char* inverse_sqrt_estimate_kind() noexcept {
#if defined(__AVX512F__)
  return "AVX-512 rsqrt14";
#elif defined(__AVX__)
  return "AVX rsqrt";
#elif defined(__SSE__)
  return "SSE rsqrt";
#else
  return "none";
#endif
}

}  // namespace sculpt::deform
