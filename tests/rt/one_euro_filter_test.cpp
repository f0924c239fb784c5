// The 1€ filter against the published cross-implementation test vector, and its rules for
// timestamps that do not increase, bad samples and reset().
#include "sculpt/rt/one_euro_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sculpt::rt {
namespace {

struct Row {
  double timestamp, signal, noisy, filtered;
};

std::vector<Row> read_ground_truth() {
  const std::string path = SCULPT_SHARED_DIR "/data/oneeuro/groundTruth.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  std::getline(in, line);
  if (line != "timestamp,signal,noisy,filtered") throw std::runtime_error("unexpected header: " + line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream s(line);
    Row r{};
    char c1 = 0, c2 = 0, c3 = 0;
    s >> r.timestamp >> c1 >> r.signal >> c2 >> r.noisy >> c3 >> r.filtered;
    if (!s || c1 != ',' || c2 != ',' || c3 != ',') throw std::runtime_error("bad row: " + line);
    rows.push_back(r);
  }
  return rows;
}

// The parameters the reference vector was produced with (its README).
const OneEuroParams kReferenceParams{1.0, 0.1, 1.0};
constexpr double kReferenceRate = 120.0;

TEST(OneEuroFilter, MatchesTheReferenceVectorOnEveryRow) {
  const std::vector<Row> rows = read_ground_truth();
  ASSERT_EQ(rows.size(), 1200u);
  OneEuroFilter f(kReferenceParams, kReferenceRate);
  double worst = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double out = f.filter(rows[i].noisy, rows[i].timestamp);
    ASSERT_LE(std::abs(out - rows[i].filtered), 1e-4) << "row " << i << " t=" << rows[i].timestamp;
    worst = std::max(worst, std::abs(out - rows[i].filtered));
  }
  // Tighter than the reference's 1e-4, to catch a wrong formula hiding under it. The residual
  // is the CSV's rounding: timestamps are printed to 6 significant digits, so past t = 1 s each
  // 8.3 ms interval carries up to 1e-5 s of rounding (0.1 % rate jitter), worth 2.4e-5 here;
  // with the rate fixed at 120 Hz the same rows agree to 4e-6.
  EXPECT_LT(worst, 5e-5);
}

TEST(OneEuroFilter, ThreeAxisFilterMatchesTheReferenceOnEachAxis) {
  const std::vector<Row> rows = read_ground_truth();
  OneEuroFilter3 f(kReferenceParams, kReferenceRate);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    // Same signal on x, negated on y, shifted on z: the filter is linear in offset and sign
    // (|dx| is unchanged), so each axis must follow the reference.
    const auto out = f.filter({rows[i].noisy, -rows[i].noisy, rows[i].noisy + 10.0}, rows[i].timestamp);
    ASSERT_LE(std::abs(out[0] - rows[i].filtered), 1e-4) << "row " << i;
    ASSERT_LE(std::abs(out[1] + rows[i].filtered), 1e-4) << "row " << i;
    ASSERT_LE(std::abs(out[2] - 10.0 - rows[i].filtered), 1e-4) << "row " << i;
  }
}

TEST(OneEuroFilter, FirstSamplePassesThrough) {
  OneEuroFilter f(kReferenceParams, kReferenceRate);
  EXPECT_FALSE(f.has_output());
  EXPECT_EQ(f.filter(3.25, 10.0), 3.25);
  EXPECT_TRUE(f.has_output());
}

TEST(OneEuroFilter, ConstantSignalStaysExact) {
  OneEuroFilter f({0.5, 0.7, 1.0}, 100.0);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(f.filter(-2.5, i * 0.01), -2.5);
}

// With beta = 0 the filter is a fixed first-order low-pass: its step response at a constant
// rate is 1 - (1 - alpha)^k exactly, alpha = 1 / (1 + tau / te).
TEST(OneEuroFilter, WithoutBetaIsTheClassicLowPass) {
  const double fc = 2.0, rate = 200.0;
  OneEuroFilter f({fc, 0.0, 1.0}, rate);
  f.filter(0.0, 0.0);
  const double alpha = 1.0 / (1.0 + (1.0 / (2.0 * std::numbers::pi * fc)) * rate);
  for (int k = 1; k <= 200; ++k) {
    const double out = f.filter(1.0, k / rate);
    EXPECT_NEAR(out, 1.0 - std::pow(1.0 - alpha, k), 1e-12) << "k=" << k;
  }
}

// A larger beta raises the cutoff with speed: the output lags a ramp less.
TEST(OneEuroFilter, BetaReducesLagOnARamp) {
  OneEuroFilter slow({1.0, 0.0, 1.0}, 100.0), fast({1.0, 1.0, 1.0}, 100.0);
  double out_slow = 0.0, out_fast = 0.0;
  for (int k = 0; k <= 100; ++k) {
    out_slow = slow.filter(k * 0.05, k * 0.01);
    out_fast = fast.filter(k * 0.05, k * 0.01);
  }
  const double truth = 100 * 0.05;
  EXPECT_LT(truth - out_fast, 0.5 * (truth - out_slow));
  EXPECT_GT(truth - out_fast, 0.0);
}

// Rule: a timestamp that does not increase keeps the last rate (no division by zero or a
// negative rate), and becomes the latest timestamp.
TEST(OneEuroFilter, NonIncreasingTimestampKeepsTheLastRateAndStaysFinite) {
  OneEuroFilter f(kReferenceParams, kReferenceRate);
  f.filter(0.0, 1.00);
  f.filter(0.1, 1.01);
  EXPECT_NEAR(f.rate_hz(), 100.0, 1e-9);
  const double repeated = f.filter(0.2, 1.01);  // same timestamp
  EXPECT_TRUE(std::isfinite(repeated));
  EXPECT_NEAR(f.rate_hz(), 100.0, 1e-9);
  const double backwards = f.filter(0.3, 0.5);  // earlier timestamp
  EXPECT_TRUE(std::isfinite(backwards));
  EXPECT_NEAR(f.rate_hz(), 100.0, 1e-9);
  // The rate is then measured from the backwards timestamp: the source's clock restarted.
  f.filter(0.3, 0.52);
  EXPECT_NEAR(f.rate_hz(), 50.0, 1e-9);
  const double nan_time = f.filter(0.4, std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isfinite(nan_time));
  EXPECT_NEAR(f.rate_hz(), 50.0, 1e-9);

  // The same samples, with the repeated timestamp, give what a filter told the rate directly
  // gives: the repeated sample is filtered at the last rate, not skipped.
  OneEuroFilter g(kReferenceParams, 100.0);
  g.filter(0.0, 0.0);
  g.filter(0.1, 0.01);
  EXPECT_NEAR(repeated, g.filter(0.2, 0.01), 1e-12);
}

TEST(OneEuroFilter, NonFiniteValueIsIgnored) {
  OneEuroFilter f(kReferenceParams, kReferenceRate);
  f.filter(1.0, 0.0);
  const double before = f.filter(2.0, 0.01);
  EXPECT_EQ(f.filter(std::numeric_limits<double>::quiet_NaN(), 0.02), before);
  EXPECT_EQ(f.filter(std::numeric_limits<double>::infinity(), 0.03), before);
  EXPECT_TRUE(std::isfinite(f.filter(2.0, 0.04)));

  OneEuroFilter3 g(kReferenceParams, kReferenceRate);
  const auto first = g.filter({1.0, 2.0, 3.0}, 0.0);
  const auto held = g.filter({5.0, std::numeric_limits<double>::quiet_NaN(), 5.0}, 0.01);
  EXPECT_EQ(held, first) << "a point with one bad coordinate is ignored as a whole";
}

TEST(OneEuroFilter, ResetStartsAgainExactlyAsNew) {
  const std::vector<Row> rows = read_ground_truth();
  OneEuroFilter f(kReferenceParams, kReferenceRate);
  for (int i = 0; i < 300; ++i) f.filter(rows[i].noisy * 7.0 + 3.0, rows[i].timestamp * 0.5);
  f.reset();
  EXPECT_FALSE(f.has_output());
  EXPECT_EQ(f.rate_hz(), kReferenceRate);
  OneEuroFilter fresh(kReferenceParams, kReferenceRate);
  for (const Row& r : rows) ASSERT_EQ(f.filter(r.noisy, r.timestamp), fresh.filter(r.noisy, r.timestamp));

  OneEuroFilter3 g(kReferenceParams, kReferenceRate);
  g.filter({1.0, 2.0, 3.0}, 0.0);
  g.filter({4.0, 5.0, 6.0}, 0.01);
  g.reset();
  EXPECT_FALSE(g.has_output());
  const std::array<double, 3> p{-1.0, -2.0, -3.0};
  EXPECT_EQ(g.filter(p, 5.0), p);
}

TEST(OneEuroFilter, RejectsBadParameters) {
  EXPECT_THROW(OneEuroFilter({0.0, 0.1, 1.0}, 120.0), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter({1.0, -0.1, 1.0}, 120.0), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter({1.0, 0.1, 0.0}, 120.0), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter({std::nan(""), 0.1, 1.0}, 120.0), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter(kReferenceParams, 0.0), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter(kReferenceParams, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(OneEuroFilter3({1.0, 0.1, -1.0}, 120.0), std::invalid_argument);
  try {
    OneEuroFilter({-2.0, 0.1, 1.0}, 120.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("min_cutoff"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::rt
