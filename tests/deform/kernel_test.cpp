// The kernels against independent truths: Navier's equation, the stress tensor of a numerical
// gradient, central differences, reciprocity, and the eps -> 0 limit.
#include "sculpt/deform/kernel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace sculpt::deform {
namespace {

Kernel kelvin(double g, double nu) { return {KernelKind::kKelvin, {g, nu}, 0.0}; }
Kernel regularized(double g, double nu, double eps) { return {KernelKind::kRegularized, {g, nu}, eps}; }

double max_abs(const Vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

Vec3 unit_axis(int i) {
  Vec3 e;
  e[i] = 1.0;
  return e;
}

// Central-difference gradient of the displacement: grad(l, m) = d u_l / d Q_m.
Mat3 numerical_gradient(const Kernel& k, const Vec3& p, const Vec3& f, const Vec3& q, double h) {
  Mat3 grad;
  for (int m = 0; m < 3; ++m) {
    const Vec3 plus = displacement(k, p, f, q + unit_axis(m) * h);
    const Vec3 minus = displacement(k, p, f, q - unit_axis(m) * h);
    for (int l = 0; l < 3; ++l) grad(l, m) = (plus[l] - minus[l]) / (2.0 * h);
  }
  return grad;
}

struct Case {
  Vec3 source, force, point, normal;
};

std::vector<Case> random_cases(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Case> cases;
  while (static_cast<int>(cases.size()) < count) {
    Case c{{u(rng), u(rng), u(rng)},
           {u(rng), u(rng), u(rng)},
           {u(rng), u(rng), u(rng)},
           normalized(Vec3{u(rng), u(rng), u(rng)})};
    if (norm(c.point - c.source) > 0.3) cases.push_back(c);
  }
  return cases;
}

// Navier: G lap(u) + (lambda + G) grad(div u) = 0 away from the source, checked with a
// fourth-order-accurate finite-difference stencil on the displacement only.
TEST(KelvinKernel, SatisfiesNaviersEquationAwayFromTheSource) {
  for (double nu : {0.0, 0.3, 0.45, 0.49}) {
    const double g = 3e7;
    const double lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
    const Kernel k = kelvin(g, nu);
    for (const Case& c : random_cases(7, 20)) {
      const Vec3 f = c.force * 1e7;
      const double h = 1e-3;
      auto u = [&](const Vec3& q) { return displacement(k, c.source, f, q); };
      // second derivative d^2 u / dQ_a dQ_b by central differences
      auto d2 = [&](int a, int b) {
        const Vec3 ea = unit_axis(a) * h, eb = unit_axis(b) * h;
        if (a == b) return (u(c.point + ea) - u(c.point) * 2.0 + u(c.point - ea)) * (1.0 / (h * h));
        return (u(c.point + ea + eb) - u(c.point + ea - eb) - u(c.point - ea + eb) + u(c.point - ea - eb)) *
               (1.0 / (4.0 * h * h));
      };
      Vec3 laplacian, grad_div;
      double scale = 0.0;
      for (int a = 0; a < 3; ++a) {
        const Vec3 daa = d2(a, a);
        laplacian += daa;
        scale = std::max(scale, max_abs(daa));
        for (int b = 0; b < 3; ++b) grad_div[a] += d2(a, b)[b];  // d/dQ_a (d u_b / dQ_b)
      }
      const Vec3 residual = laplacian * g + grad_div * (lambda + g);
      EXPECT_LT(max_abs(residual), 1e-5 * (lambda + 2.0 * g) * scale)
          << "nu=" << nu << " R=" << norm(c.point - c.source);
    }
  }
}

TEST(KelvinKernel, AnalyticGradientMatchesCentralDifferences) {
  for (const Kernel& k : {kelvin(3e7, 0.45), kelvin(1e3, 0.0), regularized(3e7, 0.3, 0.2)}) {
    for (const Case& c : random_cases(11, 30)) {
      const Mat3 analytic = displacement_gradient(k, c.source, c.force, c.point);
      const Mat3 numeric = numerical_gradient(k, c.source, c.force, c.point, 1e-5);
      double scale = 0.0;
      for (int l = 0; l < 3; ++l)
        for (int m = 0; m < 3; ++m) scale = std::max(scale, std::abs(numeric(l, m)));
      for (int l = 0; l < 3; ++l)
        for (int m = 0; m < 3; ++m) EXPECT_NEAR(analytic(l, m), numeric(l, m), 1e-6 * scale);
    }
  }
}

// MATH.md §2: T^T f must equal sigma(Q) n, sigma from a numerical gradient of §1.
TEST(KelvinKernel, TractionEqualsStressOfNumericalGradientTimesNormal) {
  for (double nu : {0.0, 0.25, 0.45}) {
    const double g = 3e7;
    const double lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
    const Kernel k = kelvin(g, nu);
    for (const Case& c : random_cases(13, 30)) {
      const Mat3 grad = numerical_gradient(k, c.source, c.force, c.point, 1e-5);
      const double trace = grad(0, 0) + grad(1, 1) + grad(2, 2);
      Vec3 sigma_n;
      for (int i = 0; i < 3; ++i) {
        sigma_n[i] = lambda * trace * c.normal[i];
        for (int j = 0; j < 3; ++j) sigma_n[i] += g * (grad(i, j) + grad(j, i)) * c.normal[j];
      }
      const Vec3 t = kelvin_traction(nu, c.source, c.force, c.point, c.normal);
      const double scale = max_abs(sigma_n) + 1e-3 * norm(c.force) / squared_norm(c.point - c.source);
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(t[j], sigma_n[j], 1e-6 * scale) << "nu=" << nu;
    }
  }
}

// T f (the wrong index order) differs: the antisymmetric term flips. Guards the i/j order.
TEST(KelvinKernel, TractionIndexOrderMatters) {
  const Vec3 p{0, 0, 0}, q{1, 0.5, 0.2}, n = normalized(Vec3{0.3, 1, 0}), f{0.2, -1, 0.4};
  const Mat3 t = kelvin_traction_matrix(0.3, p, q, n);
  Vec3 wrong;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) wrong[i] += t(i, j) * f[j];
  const Vec3 right = kelvin_traction(0.3, p, f, q, n);
  EXPECT_GT(norm(right - wrong), 1e-3 * norm(right));
  const Vec3 stress = stress_traction(kelvin(5.0, 0.3), p, f, q, n);
  EXPECT_NEAR(norm(right - stress), 0.0, 1e-9 * norm(right));
}

// At nu = 0.5 lambda is infinite; the closed form and the cancelled stress stay finite and agree.
TEST(KelvinKernel, IncompressibleLimitTractionIsFiniteAndConsistent) {
  for (const Case& c : random_cases(17, 20)) {
    const Vec3 closed = kelvin_traction(0.5, c.source, c.force, c.point, c.normal);
    const Vec3 stress = stress_traction(kelvin(3e7, 0.5), c.source, c.force, c.point, c.normal);
    ASSERT_TRUE(is_finite(closed));
    EXPECT_NEAR(norm(closed - stress), 0.0, 1e-9 * norm(closed));
  }
}

TEST(KelvinKernel, ReciprocityUpqEqualsUqpTransposed) {
  for (const Kernel& k : {kelvin(3e7, 0.45), regularized(3e7, 0.45, 0.1)}) {
    for (const Case& c : random_cases(19, 20)) {
      const Mat3 pq = displacement_matrix(k, c.source, c.point);
      const Mat3 qp = displacement_matrix(k, c.point, c.source);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) EXPECT_DOUBLE_EQ(pq(a, b), qp(b, a));
    }
  }
}

TEST(KelvinKernel, DisplacementIsLinearInTheForce) {
  const Kernel k = kelvin(3e7, 0.45);
  for (const Case& c : random_cases(23, 10)) {
    const Vec3 f2{0.3, -0.7, 0.1};
    const Vec3 sum = displacement(k, c.source, c.force, c.point) + displacement(k, c.source, f2, c.point);
    const Vec3 joint = displacement(k, c.source, c.force + f2, c.point);
    EXPECT_NEAR(norm(sum - joint), 0.0, 1e-12 * norm(joint));
  }
}

TEST(RegularizedKernel, TendsToKelvinAsEpsVanishes) {
  const Kernel k = kelvin(3e7, 0.45);
  for (const Case& c : random_cases(29, 20)) {
    const Vec3 exact = displacement(k, c.source, c.force, c.point);
    double previous_error = INFINITY;
    for (double eps : {1e-1, 1e-2, 1e-3, 1e-4}) {
      const Vec3 reg = displacement(regularized(3e7, 0.45, eps), c.source, c.force, c.point);
      const double error = norm(reg - exact) / norm(exact);
      EXPECT_LT(error, previous_error);
      previous_error = error;
    }
    EXPECT_LT(previous_error, 1e-6);
  }
}

TEST(RegularizedKernel, IsFiniteAtTheSource) {
  const Kernel k = regularized(3e7, 0.45, 0.05);
  const Vec3 p{0.1, 0.2, 0.3}, f{1, 2, 3};
  const Vec3 u = displacement(k, p, f, p);
  ASSERT_TRUE(is_finite(u));
  // At R = 0 only the isotropic part survives: u = (a - b + a/2) / eps f (MATH.md §1).
  const double a = 1.0 / (4.0 * M_PI * 3e7), b = a / (4.0 * (1.0 - 0.45));
  const double expected = (a - b + a / 2.0) / 0.05;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u[i], expected * f[i], 1e-12 * expected * 3.0);
  EXPECT_TRUE(is_finite(traction(k, p, f, p, Vec3{0, 0, 1})));
}

TEST(KernelSettings, InvalidMaterialsAndRadiiAreRejected) {
  EXPECT_THROW(kelvin(0.0, 0.3).validate(), std::invalid_argument);
  EXPECT_THROW(kelvin(3e7, 0.51).validate(), std::invalid_argument);
  EXPECT_THROW(kelvin(3e7, -1.0).validate(), std::invalid_argument);
  EXPECT_NO_THROW(kelvin(3e7, 0.5).validate());
  EXPECT_THROW(regularized(3e7, 0.3, 0.0).validate(), std::invalid_argument);
  EXPECT_NO_THROW(regularized(3e7, 0.3, 0.1).validate());
  // G is bounded above too (kMaxShearModulus), and NaN fails every comparison.
  EXPECT_NO_THROW(kelvin(1e15, 0.3).validate());
  EXPECT_THROW(kelvin(1.01e15, 0.3).validate(), std::invalid_argument);
  EXPECT_THROW(kelvin(std::nan(""), 0.3).validate(), std::invalid_argument);
  EXPECT_THROW(kelvin(3e7, std::nan("")).validate(), std::invalid_argument);
  EXPECT_NO_THROW(kelvin(1e-9, 0.3).validate());
  EXPECT_NO_THROW(kelvin(1e-15, 0.3).validate());  // and below, kMinShearModulus
  EXPECT_THROW(kelvin(0.99e-15, 0.3).validate(), std::invalid_argument);
  try {
    kelvin(-1e-9, 0.3).validate();
    ADD_FAILURE() << "accepted a negative G";  // its message prints it %g-style, not 0.000000
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("got -1e-09"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::deform
