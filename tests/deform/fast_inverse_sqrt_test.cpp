// FieldOptions::fast_inverse_sqrt, a named approximation: 1/r from the processor's reciprocal
// square root estimate and one Newton step. Checked against facts that do not come from it:
// - each value is within kInverseSqrtEstimateError of 1/sqrt(x) computed in double, over the
//   whole range of normal floats and for every count (the last few values are padded to a
//   whole vector); values outside that range get exactly 1.0f / std::sqrt(x);
// - a five-finger pass with it is as close to the double pass as the float pass is (within
//   twice float's own error, positions and normals), and differs from the float pass (the
//   setting is not silently ignored);
// - the bounded pass and the second core agree with it bit for bit, and double ignores it.

#include "sculpt/deform/inverse_sqrt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/kernel.hpp"
#include "deform/five_finger_frame.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::deform {
namespace {

double relative_error(float estimate, float x) {
  const double exact = 1.0 / std::sqrt(static_cast<double>(x));
  return std::abs(static_cast<double>(estimate) - exact) / exact;
}

TEST(InverseSqrtEstimate, IsWithinItsErrorOverEveryNormalFloat) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
  std::vector<float> x;
  for (int e = -126; e <= 127; ++e) {
    x.push_back(std::ldexp(1.0f, e));
    x.push_back(std::nextafter(std::ldexp(2.0f, e), 0.0f));  // the largest of this binade
    for (int k = 0; k < 64; ++k) x.push_back(std::ldexp(mantissa(rng), e));
  }
  x.push_back(std::numeric_limits<float>::max());
  std::vector<float> y = x;
  inverse_sqrt_estimate(y.data(), y.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, relative_error(y[i], x[i]));
  std::printf("estimate (%s): worst relative error %.3g over %zu values (bound %.3g)\n", inverse_sqrt_estimate_kind(),
              worst, x.size(), kInverseSqrtEstimateError);
  EXPECT_LE(worst, kInverseSqrtEstimateError);
}

TEST(InverseSqrtEstimate, EveryCountGetsTheEstimateToTheLastValue) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(1e-4f, 1e4f);
  for (std::size_t n = 1; n <= 40; ++n) {
    SCOPED_TRACE("n = " + std::to_string(n));
    std::vector<float> x(n);
    for (float& v : x) v = u(rng);
    std::vector<float> y = x;
    y.push_back(-7.0f);  // past the count: must stay as it is
    inverse_sqrt_estimate(y.data(), n);
    for (std::size_t i = 0; i < n; ++i) EXPECT_LE(relative_error(y[i], x[i]), kInverseSqrtEstimateError) << i;
    EXPECT_EQ(y[n], -7.0f);
  }
}

TEST(InverseSqrtEstimate, ValuesOutsideItsRangeGetTheExactResult) {
  const float special[] = {0.0f,
                           -0.0f,
                           std::numeric_limits<float>::denorm_min(),
                           1e-40f,
                           std::nextafter(std::numeric_limits<float>::min(), 0.0f),
                           std::numeric_limits<float>::infinity(),
                           -1.0f,
                           -std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN()};
  // Each alone and among ordinary values (a whole vector with one lane out of range).
  for (float s : special) {
    for (std::size_t at : {std::size_t{0}, std::size_t{5}, std::size_t{17}}) {
      std::vector<float> y(20, 4.0f);
      y[at] = s;
      inverse_sqrt_estimate(y.data(), y.size());
      const float want = 1.0f / std::sqrt(s);
      if (std::isnan(want)) {
        EXPECT_TRUE(std::isnan(y[at])) << s;
      } else {
        EXPECT_EQ(std::memcmp(&y[at], &want, sizeof want), 0) << s << " gave " << y[at] << ", want " << want;
      }
      for (std::size_t i = 0; i < y.size(); ++i) {
        if (i == at) continue;
        EXPECT_LE(relative_error(y[i], 4.0f), kInverseSqrtEstimateError) << s << " at " << i;
      }
    }
  }
}

using frames::five_fingers;
using frames::Frame;
using test::same_bytes;

PointModel pass(const Frame& f, Precision precision, bool fast, double skip_bound = 0.0,
                FieldWorker* worker = nullptr) {
  PointModel m = f.base;
  FieldOptions options;
  options.precision = precision;
  options.normal_skip_bound = skip_bound;
  options.fast_inverse_sqrt = fast;
  EXPECT_TRUE(apply_displacements(m, Kernel{}, f.sources, {}, true, options, true, nullptr, worker).finite);
  return m;
}

double largest_position_gap(const PointModel& a, const PointModel& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, norm(a.position(i) - b.position(i)));
  return worst;
}

double largest_normal_angle(const PointModel& a, const PointModel& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double c = dot(a.normal(i), b.normal(i)) / (norm(a.normal(i)) * norm(b.normal(i)));
    worst = std::max(worst, std::acos(std::clamp(c, -1.0, 1.0)));
  }
  return worst;
}

TEST(FastInverseSqrt, APassIsAsCloseToTheDoublePassAsTheFloatPassIs) {
  const Frame f = five_fingers();
  const PointModel exact = pass(f, Precision::kDouble, false);
  const PointModel plain = pass(f, Precision::kFloat, false);
  const PointModel fast = pass(f, Precision::kFloat, true);
  const double float_error = largest_position_gap(plain, exact), fast_error = largest_position_gap(fast, exact);
  const double float_turn = largest_normal_angle(plain, exact), fast_turn = largest_normal_angle(fast, exact);
  std::printf("against double: positions float %.3g, fast %.3g; normals float %.3g rad, fast %.3g rad\n", float_error,
              fast_error, float_turn, fast_turn);
  EXPECT_GT(float_error, 0.0);
  EXPECT_LE(fast_error, 2.0 * float_error);
  EXPECT_LE(fast_turn, 2.0 * float_turn);
  // It did act: some position or normal differs from the plain float pass's.
  EXPECT_FALSE(same_bytes(fast, plain));
}

TEST(FastInverseSqrt, TheBoundedPassAndTheSecondCoreGiveTheSameBytes) {
  const Frame f = five_fingers();
  const PointModel fast = pass(f, Precision::kFloat, true);
  FieldWorker worker;
  EXPECT_TRUE(same_bytes(pass(f, Precision::kFloat, true, 0.0, &worker), fast));
  // Bounded: positions are the exact (here: fast) pass's, bit for bit, as without the estimate.
  const PointModel bounded = pass(f, Precision::kFloat, true, 1e-2);
  EXPECT_TRUE(same_bytes(bounded.x, fast.x) && same_bytes(bounded.y, fast.y) && same_bytes(bounded.z, fast.z));
  EXPECT_TRUE(same_bytes(pass(f, Precision::kFloat, true, 1e-2, &worker), bounded));
}

TEST(FastInverseSqrt, DoublePrecisionIgnoresIt) {
  const Frame f = five_fingers();
  EXPECT_TRUE(same_bytes(pass(f, Precision::kDouble, true), pass(f, Precision::kDouble, false)));
}

}  // namespace
}  // namespace sculpt::deform
