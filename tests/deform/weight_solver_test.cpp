// The weight solver against forces known in advance: boundary values generated from chosen
// forces must give those forces back, whatever the form, rank or duplicate rows.
#include "sculpt/deform/weight_solver.hpp"

#include <gtest/gtest.h>

// GCC 12's false -Wmaybe-uninitialized inside avx512fintrin.h (bug 105593), as in the solver.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop

#include <cmath>
#include <random>
#include <vector>

namespace sculpt::deform {
namespace {

const Kernel kKelvin{KernelKind::kKelvin, {3e7, 0.45}, 0.0};

Vec3 field(const Kernel& k, const std::vector<SourceSetup>& sources, const std::vector<Vec3>& f, const Vec3& q) {
  Vec3 u;
  for (std::size_t s = 0; s < sources.size(); ++s) u += displacement(k, sources[s].source, f[s], q);
  return u;
}

std::vector<Vec3> points_on_sphere(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> pts;
  for (int i = 0; i < count; ++i) pts.push_back(normalized(Vec3{g(rng), g(rng), g(rng)}));
  return pts;
}

TEST(WeightSolver, RecoversKnownForcesInTheForceForm) {
  const std::vector<SourceSetup> sources = {{{0, 0, 1.3}, {}}, {{1.4, 0, 0}, {}}};
  const std::vector<Vec3> truth = {{1e5, -2e5, 3e5}, {-4e5, 1e5, 2e5}};
  std::vector<DisplacementCondition> bcs;
  for (const Vec3& q : points_on_sphere(3, 12)) bcs.push_back({q, field(kKelvin, sources, truth, q)});
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(2), effective(2);
  const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.rank, 6u);
  EXPECT_EQ(r.rows, 36u);
  EXPECT_LT(r.relative_residual, 1e-10);
  for (int s = 0; s < 2; ++s) EXPECT_LT(norm(effective[s] - truth[s]), 1e-8 * norm(truth[s]));
  EXPECT_EQ(weights[0], effective[0]);
}

// Chapter 4 form with a zero force component: that column is zero, the rank drops by one and
// the effective force keeps that component at exactly zero.
TEST(WeightSolver, SurvivesZeroForceComponentsInTheScaleForm) {
  const std::vector<SourceSetup> sources = {{{0, 0, 1.3}, {0.0, 0.1, -0.2}}};
  const std::vector<Vec3> truth = {{0.0, 2e5, -1e5}};
  std::vector<DisplacementCondition> bcs;
  for (const Vec3& q : points_on_sphere(5, 8)) bcs.push_back({q, field(kKelvin, sources, truth, q)});
  WeightSolver solver({WeightForm::kScale});
  std::vector<Vec3> weights(1), effective(1);
  const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.rank, 2u);
  EXPECT_TRUE(std::isinf(r.condition));
  EXPECT_EQ(effective[0].x, 0.0);
  EXPECT_NEAR(effective[0].y, 2e5, 1e-3);
  EXPECT_NEAR(effective[0].z, -1e5, 1e-3);
  EXPECT_NEAR(weights[0].y, 2e6, 1e-2);  // alpha_k = f_k / F_k
}

TEST(WeightSolver, DuplicateBoundaryPointsAndASinglePointAreFine) {
  const std::vector<SourceSetup> sources = {{{0.2, 0.1, 1.5}, {}}};
  const std::vector<Vec3> truth = {{3e5, 1e5, -2e5}};
  const Vec3 q{0, 0, 1};
  const DisplacementCondition bc{q, field(kKelvin, sources, truth, q)};
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(1), effective(1);
  for (const std::vector<DisplacementCondition>& bcs :
       {std::vector<DisplacementCondition>{bc}, std::vector<DisplacementCondition>{bc, bc, bc, bc}}) {
    const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.rank, 3u);
    EXPECT_LT(norm(effective[0] - truth[0]), 1e-8 * norm(truth[0]));
  }
}

// Two sources at the same place cannot be told apart: rank 3 of 6, and the minimum-norm
// answer splits the force evenly while still meeting every condition.
TEST(WeightSolver, CoincidentSourcesGiveTheMinimumNormSplit) {
  const std::vector<SourceSetup> sources = {{{0, 0, 1.5}, {}}, {{0, 0, 1.5}, {}}};
  const std::vector<Vec3> truth = {{2e5, 0, -4e5}, {0, 0, 0}};
  std::vector<DisplacementCondition> bcs;
  for (const Vec3& q : points_on_sphere(9, 10)) bcs.push_back({q, field(kKelvin, sources, truth, q)});
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(2), effective(2);
  const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.rank, 3u);
  EXPECT_LT(r.relative_residual, 1e-9);
  EXPECT_LT(norm(effective[0] - truth[0] * 0.5), 1e-6 * norm(truth[0]));
  EXPECT_LT(norm(effective[1] - truth[0] * 0.5), 1e-6 * norm(truth[0]));
}

TEST(WeightSolver, TractionRowsAloneDetermineTheForce) {
  const std::vector<SourceSetup> sources = {{{0, 0, 1.4}, {}}};
  const std::vector<Vec3> truth = {{1e5, 2e5, -3e5}};
  std::vector<TractionCondition> tcs;
  for (const Vec3& q : points_on_sphere(21, 6)) {
    tcs.push_back({q, q, kelvin_traction(0.45, sources[0].source, truth[0], q, q)});
  }
  WeightSolver solver({WeightForm::kForce, /*traction_eps=*/1e-2});
  std::vector<Vec3> weights(1), effective(1);
  const SolveReport r = solver.solve(kKelvin, sources, {}, tcs, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.rank, 3u);
  EXPECT_LT(norm(effective[0] - truth[0]), 1e-8 * norm(truth[0]));
}

// The reported condition number equals the one of an independent SVD of the equilibrated
// stacked matrix, computed here without the solver's QR.
TEST(WeightSolver, ConditionEstimateMatchesAnIndependentSvdOfTheStackedRows) {
  const std::vector<SourceSetup> sources = {{{0, 0, 1.2}, {}}, {{0.3, 0, 1.2}, {}}};
  std::vector<DisplacementCondition> bcs;
  for (const Vec3& q : points_on_sphere(31, 7)) bcs.push_back({q, {0.01, 0, 0}});
  const std::size_t rows = 3 * bcs.size(), cols = 6;
  std::vector<double> a(rows * cols);
  for (std::size_t i = 0; i < bcs.size(); ++i)
    for (std::size_t s = 0; s < 2; ++s) {
      const Mat3 m = displacement_matrix(kKelvin, sources[s].source, bcs[i].point);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) a[(3 * i + c) * cols + 3 * s + k] = m(c, k);
    }
  for (std::size_t j = 0; j < cols; ++j) {
    double n = 0;
    for (std::size_t i = 0; i < rows; ++i) n += a[i * cols + j] * a[i * cols + j];
    for (std::size_t i = 0; i < rows; ++i) a[i * cols + j] /= std::sqrt(n);
  }
  // Eigenvalues of A^T A by Jacobi rotations (a tiny independent implementation).
  std::vector<double> ata(cols * cols, 0.0);
  for (std::size_t i = 0; i < cols; ++i)
    for (std::size_t j = 0; j < cols; ++j)
      for (std::size_t k = 0; k < rows; ++k) ata[i * cols + j] += a[k * cols + i] * a[k * cols + j];
  for (int sweep = 0; sweep < 50; ++sweep)
    for (std::size_t p = 0; p < cols; ++p)
      for (std::size_t q = p + 1; q < cols; ++q) {
        const double apq = ata[p * cols + q];
        if (std::abs(apq) < 1e-300) continue;
        const double theta = (ata[q * cols + q] - ata[p * cols + p]) / (2 * apq);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (std::size_t k = 0; k < cols; ++k) {
          const double akp = ata[k * cols + p], akq = ata[k * cols + q];
          ata[k * cols + p] = c * akp - s * akq;
          ata[k * cols + q] = s * akp + c * akq;
        }
        for (std::size_t k = 0; k < cols; ++k) {
          const double apk = ata[p * cols + k], aqk = ata[q * cols + k];
          ata[p * cols + k] = c * apk - s * aqk;
          ata[q * cols + k] = s * apk + c * aqk;
        }
      }
  double lo = INFINITY, hi = 0;
  for (std::size_t i = 0; i < cols; ++i) {
    lo = std::min(lo, ata[i * cols + i]);
    hi = std::max(hi, ata[i * cols + i]);
  }
  const double expected = std::sqrt(hi / lo);
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(2), effective(2);
  const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.condition, expected, 1e-4 * expected);
  EXPECT_GT(r.condition, 10.0);  // two close sources: genuinely ill-conditioned
}

// The blocked QR against an independent dense least-squares solve (Eigen's complete orthogonal
// decomposition on the stacked, weighted rows built here from the kernel): five sources, a
// count of conditions that fills several blocks and leaves a partial one, weights that differ
// row by row, and targets no force meets exactly (so the residual is not zero).
struct DenseFit {
  std::vector<Vec3> forces;
  double residual = 0.0;
  double rhs_norm = 0.0;
};

DenseFit dense_fit(const Kernel& k, const std::vector<SourceSetup>& sources,
                   const std::vector<DisplacementCondition>& bcs) {
  const auto rows = static_cast<Eigen::Index>(3 * bcs.size());
  const auto cols = static_cast<Eigen::Index>(3 * sources.size());
  Eigen::MatrixXd a(rows, cols);
  Eigen::VectorXd b(rows);
  for (std::size_t i = 0; i < bcs.size(); ++i) {
    for (std::size_t s = 0; s < sources.size(); ++s) {
      const Mat3 m = displacement_matrix(k, sources[s].source, bcs[i].point);
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < 3; ++j)
          a(static_cast<Eigen::Index>(3 * i) + c, static_cast<Eigen::Index>(3 * s) + j) = bcs[i].weight * m(c, j);
    }
    for (int c = 0; c < 3; ++c) b(static_cast<Eigen::Index>(3 * i) + c) = bcs[i].weight * bcs[i].displacement[c];
  }
  const Eigen::VectorXd x = a.completeOrthogonalDecomposition().solve(b);
  DenseFit fit;
  for (std::size_t s = 0; s < sources.size(); ++s) {
    const auto j = static_cast<Eigen::Index>(3 * s);
    fit.forces.push_back({x(j), x(j + 1), x(j + 2)});
  }
  fit.residual = (a * x - b).norm();
  fit.rhs_norm = b.norm();
  return fit;
}

std::vector<SourceSetup> five_sources() {
  std::vector<SourceSetup> sources;
  for (int s = 0; s < 5; ++s) {
    const double t = 1.3 * s;
    sources.push_back({normalized(Vec3{std::cos(t), std::sin(t), 0.4 * s - 0.8}) * 1.1, {}});
  }
  return sources;
}

std::vector<DisplacementCondition> noisy_conditions(unsigned seed, int count, double weight_scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.5, 2.0);
  std::vector<DisplacementCondition> bcs;
  const std::vector<Vec3> pts = points_on_sphere(seed + 1, count);
  for (int i = 0; i < count; ++i) {
    bcs.push_back({pts[static_cast<std::size_t>(i)], Vec3{u(rng), u(rng), u(rng)} * 1e-3, weight_scale * w(rng)});
  }
  return bcs;
}

TEST(WeightSolver, BlockedFactorMatchesADenseLeastSquaresSolve) {
  const std::vector<SourceSetup> sources = five_sources();
  for (int count : {1, 5, 15, 16, 31, 32, 33, 64, 65, 445, 1001}) {
    const std::vector<DisplacementCondition> bcs = noisy_conditions(40 + static_cast<unsigned>(count), count, 1.0);
    const DenseFit truth = dense_fit(kKelvin, sources, bcs);
    WeightSolver solver({WeightForm::kForce});
    std::vector<Vec3> weights(5), effective(5);
    const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
    ASSERT_TRUE(r.ok) << count;
    EXPECT_EQ(r.rows, 3u * static_cast<std::size_t>(count));
    if (3 * count < 15) {
      // Fewer rows than unknowns: rank 3 count, the minimum-norm force meets every row.
      EXPECT_EQ(r.rank, 3u * static_cast<std::size_t>(count)) << count;
      EXPECT_LT(r.relative_residual, 1e-9) << count;
      continue;
    }
    EXPECT_EQ(r.rank, 15u) << count;
    double largest = 0.0;
    for (const Vec3& f : truth.forces) largest = std::max(largest, norm(f));
    for (std::size_t s = 0; s < 5; ++s) {
      EXPECT_LT(norm(effective[s] - truth.forces[s]), 1e-8 * largest) << count << " source " << s;
    }
    // As close as the rounding of either solve allows (a square system fits to ~1e-16).
    EXPECT_NEAR(r.residual, truth.residual, 1e-9 * truth.residual + 1e-12 * truth.rhs_norm) << count;
  }
}

// Every source count, 1 to kMaxSources: 3 to 30 unknowns, odd and even (a round-robin sweep
// gives an odd count a bye) and each of the SVD's three column lengths. The forces must match
// the dense fit and the condition number Eigen's SVD of the column-equilibrated stacked rows.
TEST(WeightSolver, EverySourceCountMatchesADenseSolveAndItsSingularValues) {
  for (std::size_t count = 1; count <= kMaxSources; ++count) {
    std::vector<SourceSetup> sources;
    for (std::size_t s = 0; s < count; ++s) {
      const double t = 0.9 * static_cast<double>(s);
      sources.push_back({normalized(Vec3{std::cos(t), std::sin(t), 0.15 * static_cast<double>(s) - 0.7}) * 1.15, {}});
    }
    const std::vector<DisplacementCondition> bcs =
        noisy_conditions(200 + static_cast<unsigned>(count), 40 * static_cast<int>(count), 1.0);
    const DenseFit truth = dense_fit(kKelvin, sources, bcs);
    WeightSolver solver({WeightForm::kForce});
    std::vector<Vec3> weights(count), effective(count);
    const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
    ASSERT_TRUE(r.ok) << count;
    ASSERT_EQ(r.rank, 3 * count) << count;
    double largest = 0.0;
    for (const Vec3& f : truth.forces) largest = std::max(largest, norm(f));
    for (std::size_t s = 0; s < count; ++s) {
      EXPECT_LT(norm(effective[s] - truth.forces[s]), 1e-7 * largest) << count << " source " << s;
    }

    const auto rows = static_cast<Eigen::Index>(3 * bcs.size());
    const auto cols = static_cast<Eigen::Index>(3 * count);
    Eigen::MatrixXd a(rows, cols);
    for (std::size_t i = 0; i < bcs.size(); ++i) {
      for (std::size_t s = 0; s < count; ++s) {
        const Mat3 m = displacement_matrix(kKelvin, sources[s].source, bcs[i].point);
        for (int c = 0; c < 3; ++c)
          for (int j = 0; j < 3; ++j)
            a(static_cast<Eigen::Index>(3 * i) + c, static_cast<Eigen::Index>(3 * s) + j) = bcs[i].weight * m(c, j);
      }
    }
    for (Eigen::Index j = 0; j < cols; ++j) a.col(j) /= a.col(j).norm();
    const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(a).singularValues();
    const double expected = sigma(0) / sigma(cols - 1);
    EXPECT_NEAR(r.condition, expected, 1e-6 * expected) << count;
  }
}

// Rows scaled far toward the ends of the double range (every condition's weight 1e-140 or
// 1e140, so their squares leave it) give the same forces: the reflector's lengths are then
// taken with the largest magnitude factored out.
TEST(WeightSolver, RowsNearTheEndsOfTheDoubleRangeGiveTheSameForces) {
  const std::vector<SourceSetup> sources = five_sources();
  const std::vector<DisplacementCondition> plain = noisy_conditions(77, 100, 1.0);
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(5), reference(5), effective(5);
  ASSERT_TRUE(solver.solve(kKelvin, sources, plain, {}, weights, reference).ok);
  for (double scale : {1e-140, 1e140}) {
    std::vector<DisplacementCondition> scaled = plain;
    for (DisplacementCondition& d : scaled) d.weight *= scale;
    const SolveReport r = solver.solve(kKelvin, sources, scaled, {}, weights, effective);
    ASSERT_TRUE(r.ok) << scale;
    EXPECT_EQ(r.rank, 15u);
    for (std::size_t s = 0; s < 5; ++s) EXPECT_LT(norm(effective[s] - reference[s]), 1e-10 * norm(reference[s]));
  }
}

// A block of displacement conditions is filled by a vectorised loop, a block holding a
// traction condition by the general one. With the traction rows weighted zero (traction eps 0)
// the system is the same, so the forces must be the same bits: both fills write the same rows.
TEST(WeightSolver, BothRowFillsWriteTheSameRows) {
  const std::vector<SourceSetup> sources = five_sources();
  const std::vector<DisplacementCondition> bcs = noisy_conditions(91, 20, 1.0);
  const std::vector<TractionCondition> tcs = {{Vec3{0, 0, 1}, Vec3{0, 0, 1}, Vec3{1.0, 2.0, 3.0}}};
  WeightSolver solver({WeightForm::kForce, /*traction_eps=*/0.0});
  std::vector<Vec3> weights(5), alone(5), mixed(5);
  ASSERT_TRUE(solver.solve(kKelvin, sources, bcs, {}, weights, alone).ok);
  ASSERT_TRUE(solver.solve(kKelvin, sources, bcs, tcs, weights, mixed).ok);
  for (std::size_t s = 0; s < 5; ++s) EXPECT_EQ(alone[s], mixed[s]) << s;
}

TEST(WeightSolver, InconsistentConditionsReportTheirResidual) {
  const std::vector<SourceSetup> sources = {{{0, 0, 2}, {}}};
  // One point asked to move two different ways: the best fit is the mean, residual |d|/sqrt(2)*...
  const Vec3 q{0, 0, 1};
  const std::vector<DisplacementCondition> bcs = {{q, {0, 0, 0.1}}, {q, {0, 0, -0.1}}};
  WeightSolver solver({WeightForm::kForce});
  std::vector<Vec3> weights(1), effective(1);
  const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(norm(effective[0]), 0.0, 1e-6);
  EXPECT_NEAR(r.residual, std::sqrt(0.02), 1e-12);
  EXPECT_NEAR(r.relative_residual, 1.0, 1e-12);
}

// Tall systems (the Gram route's size) whose targets come from known forces: the fit is exact,
// so the residual's pivot |b|^2 - |Q^T b|^2 cancels to rounding noise, about 1e-8 |b| after its
// square root where the noise is positive. The solver must notice and evaluate the residual on
// the rows instead: the reported residual is checked against one recomputed here from the
// reported forces, over several point sets (the noise's sign varies with them).
TEST(WeightSolver, AnExactTallFitReportsItsTrueResidual) {
  const std::vector<SourceSetup> sources = five_sources();
  const std::vector<Vec3> truth = {{1e5, -2e5, 3e5}, {-4e5, 1e5, 2e5}, {2e5, 2e5, -1e5}, {0, 3e5, 1e5}, {-1e5, 0, 4e5}};
  for (unsigned seed = 0; seed < 12; ++seed) {
    std::vector<DisplacementCondition> bcs;
    for (const Vec3& q : points_on_sphere(100 + seed, 300)) bcs.push_back({q, field(kKelvin, sources, truth, q)});
    WeightSolver solver({WeightForm::kForce});
    std::vector<Vec3> weights(5), effective(5);
    const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
    ASSERT_TRUE(r.ok) << seed;
    EXPECT_EQ(r.rank, 15u) << seed;
    double residual2 = 0.0, rhs2 = 0.0;
    for (const DisplacementCondition& d : bcs) {
      const Vec3 miss = field(kKelvin, sources, effective, d.point) - d.displacement;
      residual2 += dot(miss, miss);
      rhs2 += dot(d.displacement, d.displacement);
    }
    EXPECT_NEAR(r.residual, std::sqrt(residual2), 1e-13 * std::sqrt(rhs2)) << seed;
    for (std::size_t s = 0; s < 5; ++s) EXPECT_LT(norm(effective[s] - truth[s]), 1e-9 * norm(truth[s])) << seed;
  }
}

// Two sources drawn together, 1 to 1e-4 apart over 200 conditions: the condition number climbs
// from about 3 to past 1e6, across the limit where the solver stops trusting its Gram matrix and
// its direct solve and turns to reflections and the SVD. On both sides the condition must match
// Eigen's SVD of the equilibrated stacked rows, and the forces a dense least-squares fit.
TEST(WeightSolver, EveryRouteMatchesTheDenseSolveAsTheConditionGrows) {
  bool below = false, above = false;
  for (double gap : {1.0, 0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3, 3e-4, 1e-4}) {
    const std::vector<SourceSetup> sources = {{{0, 0, 1.2}, {}}, {{gap, 0, 1.2}, {}}};
    const std::vector<DisplacementCondition> bcs = noisy_conditions(7, 200, 1.0);
    const DenseFit truth = dense_fit(kKelvin, sources, bcs);
    Eigen::MatrixXd a(600, 6);
    for (std::size_t i = 0; i < bcs.size(); ++i) {
      for (std::size_t s = 0; s < 2; ++s) {
        const Mat3 m = displacement_matrix(kKelvin, sources[s].source, bcs[i].point);
        for (int c = 0; c < 3; ++c)
          for (int j = 0; j < 3; ++j)
            a(static_cast<Eigen::Index>(3 * i) + c, static_cast<Eigen::Index>(3 * s) + j) = bcs[i].weight * m(c, j);
      }
    }
    for (Eigen::Index j = 0; j < 6; ++j) a.col(j) /= a.col(j).norm();
    const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(a).singularValues();
    const double expected = sigma(0) / sigma(5);
    (expected < 1e3 ? below : above) = true;

    WeightSolver solver({WeightForm::kForce});
    std::vector<Vec3> weights(2), effective(2);
    const SolveReport r = solver.solve(kKelvin, sources, bcs, {}, weights, effective);
    ASSERT_TRUE(r.ok) << gap;
    EXPECT_EQ(r.rank, 6u) << gap;
    EXPECT_NEAR(r.condition, expected, 1e-6 * expected) << gap;
    double largest = 0.0;
    for (const Vec3& f : truth.forces) largest = std::max(largest, norm(f));
    // A least-squares solution loses about kappa eps of its digits, whatever the method.
    for (std::size_t s = 0; s < 2; ++s)
      EXPECT_LT(norm(effective[s] - truth.forces[s]), 1e-12 * expected * largest + 1e-9 * largest) << gap;
    EXPECT_NEAR(r.residual, truth.residual, 1e-9 * truth.residual) << gap;
  }
  EXPECT_TRUE(below && above);
}

TEST(WeightSolver, NothingToSolveIsNotOk) {
  WeightSolver solver;
  std::vector<Vec3> weights(1), effective(1);
  const std::vector<SourceSetup> sources = {{{0, 0, 2}, {0, 0, -1}}};
  EXPECT_FALSE(solver.solve(kKelvin, sources, {}, {}, weights, effective).ok);
  EXPECT_FALSE(solver.solve(kKelvin, {}, {}, {}, weights, effective).ok);
}

}  // namespace
}  // namespace sculpt::deform
