// The similarity transform against closed forms (known rotations, the inverse and composition
// laws), and Umeyama calibration recovering known transforms, reporting noise, refusing
// reflections and degenerate landmarks.
#include "sculpt/rt/similarity_transform.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace sculpt::rt {
namespace {

using V = std::array<double, 3>;
constexpr double kPi = std::numbers::pi;

double distance(const V& a, const V& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

double det(const Matrix3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

double max_abs_difference(const Matrix3& a, const Matrix3& b) {
  double d = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) d = std::max(d, std::abs(a[i][j] - b[i][j]));
  }
  return d;
}

void expect_proper_rotation(const Matrix3& r) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double dot = r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j];
      EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
    }
  }
  EXPECT_NEAR(det(r), 1.0, 1e-12);
}

// A random similarity from a uniformly random unit quaternion (Shoemake's method).
SimilarityTransform random_similarity(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0), t(-5.0, 5.0), log_scale(-2.0, 2.0);
  const double u1 = u(rng), u2 = u(rng), u3 = u(rng);
  const Quaternion q{std::sqrt(1 - u1) * std::sin(2 * kPi * u2), std::sqrt(1 - u1) * std::cos(2 * kPi * u2),
                     std::sqrt(u1) * std::sin(2 * kPi * u3), std::sqrt(u1) * std::cos(2 * kPi * u3)};
  return SimilarityTransform::from_scale_rotation_translation(std::exp(log_scale(rng)), q, {t(rng), t(rng), t(rng)});
}

std::vector<V> random_points(std::mt19937& rng, int n, double extent) {
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<V> p(static_cast<std::size_t>(n));
  for (V& x : p) x = {u(rng), u(rng), u(rng)};
  return p;
}

TEST(SimilarityTransform, DefaultIsTheIdentity) {
  const SimilarityTransform id;
  EXPECT_EQ(id.apply({1.5, -2.0, 3.0}), (V{1.5, -2.0, 3.0}));
  EXPECT_EQ(id.scale(), 1.0);
}

TEST(SimilarityTransform, KnownRotationsMapTheAxes) {
  // 90 degrees about z, as a quaternion and as an axis-angle: x -> y, y -> -x.
  const double h = std::sqrt(0.5);
  const auto q = SimilarityTransform::from_scale_rotation_translation(2.0, Quaternion{h, 0, 0, h}, {1, 2, 3});
  const auto a = SimilarityTransform::from_scale_rotation_translation(2.0, AxisAngle{{0, 0, 5}, kPi / 2}, {1, 2, 3});
  for (const auto* t : {&q, &a}) {
    const V x = t->apply({1, 0, 0});
    EXPECT_NEAR(x[0], 1.0, 1e-15);
    EXPECT_NEAR(x[1], 4.0, 1e-15);
    EXPECT_NEAR(x[2], 3.0, 1e-15);
    const V y = t->apply_vector({0, 1, 0});
    EXPECT_NEAR(y[0], -2.0, 1e-15);
    EXPECT_NEAR(y[1], 0.0, 1e-15);
    EXPECT_NEAR(y[2], 0.0, 1e-15);
  }
  // 120 degrees about (1,1,1) permutes the axes cyclically: x -> y -> z -> x.
  const auto c =
      SimilarityTransform::from_scale_rotation_translation(1.0, AxisAngle{{1, 1, 1}, 2 * kPi / 3}, {0, 0, 0});
  const V z = c.apply({0, 1, 0});
  EXPECT_NEAR(z[0], 0.0, 1e-15);
  EXPECT_NEAR(z[1], 0.0, 1e-15);
  EXPECT_NEAR(z[2], 1.0, 1e-15);
}

TEST(SimilarityTransform, QuaternionRoundTrips) {
  std::mt19937 rng(3);
  for (int i = 0; i < 100; ++i) {
    const SimilarityTransform t = random_similarity(rng);
    const Quaternion q = t.quaternion();
    EXPECT_GE(q.w, 0.0);
    const auto back = SimilarityTransform::from_scale_rotation_translation(t.scale(), q, t.translation());
    EXPECT_LT(max_abs_difference(back.rotation(), t.rotation()), 1e-14);
    expect_proper_rotation(t.rotation());
  }
}

TEST(SimilarityTransform, InverseAndComposeObeyTheirLaws) {
  std::mt19937 rng(5);
  for (int i = 0; i < 50; ++i) {
    const SimilarityTransform a = random_similarity(rng), b = random_similarity(rng);
    for (const V& p : random_points(rng, 5, 3.0)) {
      const V ab = (a * b).apply(p);
      const V by_hand = a.apply(b.apply(p));
      EXPECT_LT(distance(ab, by_hand),
                1e-12 * (1 + std::abs(by_hand[0]) + std::abs(by_hand[1]) + std::abs(by_hand[2])));
      EXPECT_LT(distance(a.inverse().apply(a.apply(p)), p), 1e-12);
      EXPECT_LT(distance(a.compose(a.inverse()).apply(p), p), 1e-12);
    }
    EXPECT_NEAR((a * b).scale(), a.scale() * b.scale(), 1e-15 * a.scale() * b.scale());
    expect_proper_rotation((a * b).rotation());
  }
}

TEST(SimilarityTransform, QuaternionNearUnitIsNormalisedFarFromUnitIsRejected) {
  const double h = std::sqrt(0.5) * (1 + 5e-7);  // norm off by 5e-7: accepted
  const auto t = SimilarityTransform::from_scale_rotation_translation(1.0, Quaternion{h, 0, 0, h}, {0, 0, 0});
  expect_proper_rotation(t.rotation());
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, Quaternion{1.01, 0, 0, 0}, {0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, Quaternion{0, 0, 0, 0}, {0, 0, 0}),
               std::invalid_argument);
  try {
    SimilarityTransform::from_scale_rotation_translation(1.0, Quaternion{2, 0, 0, 0}, {0, 0, 0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("norm 2"), std::string::npos) << e.what();
  }
}

TEST(SimilarityTransform, RejectsInvalidParameters) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Quaternion id{};
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(0.0, id, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(-1.0, id, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(nan, id, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, id, {0, nan, 0}), std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, Quaternion{nan, 0, 0, 0}, {0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, AxisAngle{{0, 0, 0}, 1.0}, {0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, AxisAngle{{0, 0, 1}, nan}, {0, 0, 0}),
               std::invalid_argument);
  // A zero angle needs no axis.
  EXPECT_NO_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, AxisAngle{{0, 0, 0}, 0.0}, {0, 0, 0}));
  const Matrix3 mirror{{{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  const Matrix3 sheared{{{1, 0.1, 0}, {0, 1, 0}, {0, 0, 1}}};
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, mirror, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(SimilarityTransform::from_scale_rotation_translation(1.0, sheared, {0, 0, 0}), std::invalid_argument);
}

// Calibration ------------------------------------------------------------------------------

void expect_recovers(const SimilarityTransform& truth, const Calibration& c, double tolerance) {
  EXPECT_NEAR(c.transform.scale(), truth.scale(), tolerance * truth.scale());
  EXPECT_LT(max_abs_difference(c.transform.rotation(), truth.rotation()), tolerance);
  EXPECT_LT(distance(c.transform.translation(), truth.translation()), tolerance * 10);
  expect_proper_rotation(c.transform.rotation());
}

TEST(Calibration, RecoversAKnownSimilarityFromThreePoints) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const SimilarityTransform truth = random_similarity(rng);
    const std::vector<V> glove = random_points(rng, 3, 1.0);
    std::vector<V> model;
    for (const V& g : glove) model.push_back(truth.apply(g));
    const Calibration c = calibrate_umeyama(glove, model);
    // Three points are coplanar: this is the case where det(U) det(V) may come out -1 for a
    // proper rotation, and the fix must still give the right rotation.
    expect_recovers(truth, c, 1e-9);
    EXPECT_LT(c.max_residual, 1e-9);
  }
}

TEST(Calibration, RecoversAKnownSimilarityFromTwentyPoints) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 50; ++trial) {
    const SimilarityTransform truth = random_similarity(rng);
    const std::vector<V> glove = random_points(rng, 20, 0.2);
    std::vector<V> model;
    for (const V& g : glove) model.push_back(truth.apply(g));
    const Calibration c = calibrate_umeyama(glove, model);
    expect_recovers(truth, c, 1e-10);
    EXPECT_LT(c.rms_residual, 1e-10);
    EXPECT_LE(c.rms_residual, c.max_residual);
  }
}

TEST(Calibration, ReportsResidualsAtTheNoiseLevel) {
  std::mt19937 rng(13);
  const double sigma = 1e-3;  // per coordinate, model units
  std::normal_distribution<double> noise(0.0, sigma);
  const SimilarityTransform truth = random_similarity(rng);
  const int n = 400;
  const std::vector<V> glove = random_points(rng, n, 1.0);
  std::vector<V> model;
  for (const V& g : glove) {
    V m = truth.apply(g);
    for (double& c : m) c += noise(rng);
    model.push_back(m);
  }
  const Calibration c = calibrate_umeyama(glove, model);
  // The least-squares fit absorbs 7 of the 3n degrees of freedom: the expected rms residual is
  // sigma sqrt(3 (n - 7 / 3) / n), i.e. sigma sqrt(3) to within 0.3 % here.
  const double expected = sigma * std::sqrt(3.0);
  EXPECT_NEAR(c.rms_residual, expected, 0.1 * expected);
  EXPECT_GT(c.max_residual, c.rms_residual);
  EXPECT_LT(c.max_residual, 6 * sigma);
  // And the transform is close to the truth at the noise level divided by sqrt(n), scaled.
  expect_recovers(truth, c, 1e-3);
  // The residuals reported are the residuals of the transform returned.
  double sum = 0.0, worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const double e =
        distance(c.transform.apply(glove[static_cast<std::size_t>(i)]), model[static_cast<std::size_t>(i)]);
    sum += e * e;
    worst = std::max(worst, e);
  }
  EXPECT_NEAR(c.rms_residual, std::sqrt(sum / n), 1e-15);
  EXPECT_EQ(c.max_residual, worst);
}

TEST(Calibration, AMirroredDataSetStillGivesAProperRotation) {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 20; ++trial) {
    const SimilarityTransform truth = random_similarity(rng);
    const std::vector<V> glove = random_points(rng, 12, 1.0);
    std::vector<V> model;
    for (const V& g : glove) model.push_back(truth.apply({-g[0], g[1], g[2]}));  // a reflection first
    const Calibration c = calibrate_umeyama(glove, model);
    expect_proper_rotation(c.transform.rotation());
    EXPECT_GT(c.transform.scale(), 0.0);
    // No rotation can fit a mirror image: the residual says so.
    EXPECT_GT(c.rms_residual, 0.05 * truth.scale());
  }
}

TEST(Calibration, RejectsTooFewMismatchedAndDegenerateLandmarks) {
  const std::vector<V> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(calibrate_umeyama(two, two), std::invalid_argument);
  const std::vector<V> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<V> four{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_THROW(calibrate_umeyama(three, four), std::invalid_argument);
  const std::vector<V> collinear{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-3.5, -3.5, -3.5}};
  EXPECT_THROW(calibrate_umeyama(collinear, four), std::invalid_argument);
  EXPECT_THROW(calibrate_umeyama(four, collinear), std::invalid_argument);
  const std::vector<V> coincident{{1, 2, 3}, {1, 2, 3}, {1, 2, 3}};
  EXPECT_THROW(calibrate_umeyama(coincident, three), std::invalid_argument);
  const std::vector<V> with_nan{{0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<double>::quiet_NaN(), 0}};
  EXPECT_THROW(calibrate_umeyama(with_nan, three), std::invalid_argument);
  try {
    calibrate_umeyama(collinear, four);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("collinear"), std::string::npos) << e.what();
  }
  try {
    calibrate_umeyama(two, two);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::rt
