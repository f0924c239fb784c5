#include "sculpt/deform/weight_solver.hpp"

// GCC 12 reports a false -Wmaybe-uninitialized inside avx512fintrin.h when Eigen's small
// fixed-size kernels are inlined with -march=native (GCC bug 105593); nothing here is read
// uninitialised.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <limits>

namespace sculpt::deform {
namespace {

constexpr int kMaxUnknowns = 3 * static_cast<int>(kMaxSources);
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxUnknowns, kMaxUnknowns>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxUnknowns, 1>;

// sqrt(a^2 + b^2) without a libm call (std::hypot was a quarter of a region frame, one call
// per Givens rotation). The plain formula is used where neither square can overflow or
// underflow (|a|, |b| within 2^-500..2^500, every real row here); outside it the larger
// magnitude is factored out, as hypot does. Either is within a few ulps of the exact length.
inline double rotation_length(double a, double b) {
  constexpr double kSafeMax = 0x1p500, kSafeMin = 0x1p-500;
  const double big = std::max(std::abs(a), std::abs(b));
  const double small = std::min(std::abs(a), std::abs(b));
  if (big < kSafeMax && small > kSafeMin) return std::sqrt(a * a + b * b);
  if (big == 0.0) return 0.0;
  const double ratio = small / big;
  return big * std::sqrt(1.0 + ratio * ratio);
}

// The upper-triangular factor R of [A | b] built one row at a time with Givens rotations:
// after all rows, R(0:n, 0:n) is A's R, R(0:n, n) is Q^T b and |R(n, n)| the residual of the
// unconstrained fit. Each row costs O(n^2) and the whole stays (n + 1)^2 doubles.
class StreamingQr {
 public:
  explicit StreamingQr(int unknowns) : n_(unknowns) {
    for (auto& row : r_) row.fill(0.0);
  }

  void add_row(std::array<double, kMaxUnknowns + 1>& row) {
    for (int k = 0; k <= n_; ++k) {
      const double a = r_[k][k], b = row[k];
      if (b == 0.0) continue;
      const double h = rotation_length(a, b);
      const double inv = 1.0 / h;
      const double c = a * inv, s = b * inv;
      for (int j = k; j <= n_; ++j) {
        const double rk = r_[k][j], xj = row[j];
        r_[k][j] = c * rk + s * xj;
        row[j] = -s * rk + c * xj;
      }
    }
  }

  double at(int i, int j) const { return r_[i][j]; }

 private:
  int n_;
  std::array<std::array<double, kMaxUnknowns + 1>, kMaxUnknowns + 1> r_;
};

// Fills the three rows (one per displacement or traction component) that a condition
// contributes: rows[c][3 s + k] is the coefficient of unknown (s, k).
struct RowBlock {
  std::array<std::array<double, kMaxUnknowns + 1>, 3> rows{};
};

}  // namespace

void SolverOptions::validate() const {
  auto fail = [](const char* what) { throw std::invalid_argument(std::string("solver: ") + what); };
  if (!(traction_eps >= 0.0) || !std::isfinite(traction_eps)) fail("traction eps must be finite and >= 0");
  if (!(rank_tolerance > 0.0 && rank_tolerance < 1e-3)) fail("rank tolerance must lie in (0, 1e-3)");
  if (!(max_condition > 1.0) || !std::isfinite(max_condition)) fail("max condition must be finite and > 1");
  if (!(rank_tolerance * max_condition < 1.0)) {
    fail("max condition must stay below 1 / rank tolerance, or the damped solve could never act");
  }
  if (!(zero_component >= 0.0 && zero_component < 1.0)) fail("zero component must lie in [0, 1)");
}

SolveReport WeightSolver::solve(const Kernel& kernel, std::span<const SourceSetup> sources,
                                std::span<const DisplacementCondition> displacements,
                                std::span<const TractionCondition> tractions, std::span<Vec3> weights,
                                std::span<Vec3> effective) const noexcept {
  SolveReport report;
  const std::size_t n = std::min({sources.size(), kMaxSources, weights.size(), effective.size()});
  const int unknowns = static_cast<int>(3 * n);
  report.unknowns = static_cast<std::size_t>(unknowns);
  report.rows = 3 * (displacements.size() + tractions.size());
  for (std::size_t s = 0; s < n; ++s) weights[s] = effective[s] = Vec3{};
  if (n == 0 || report.rows == 0) return report;

  const double young = kernel.material.young_modulus();
  const double traction_weight = std::sqrt(options_.traction_eps / (young * young));
  const bool scaled = options_.form == WeightForm::kScale;
  const KernelCoefficients coeffs = coefficients(kernel);
  const double zero_fraction = options_.zero_component;
  auto scaled_component = [zero_fraction](const Vec3& f, int k) {
    return std::abs(f[k]) <= zero_fraction * norm(f) ? 0.0 : f[k];
  };

  // Builds the rows of condition `index` (displacements first, then tractions), weighted.
  auto fill = [&](std::size_t index, RowBlock& block) {
    for (auto& row : block.rows) row.fill(0.0);
    const bool is_displacement = index < displacements.size();
    double w = 1.0;
    Vec3 target;
    for (std::size_t s = 0; s < n; ++s) {
      Mat3 m;  // m(c, k): component c of the row quantity per unit force component k
      if (is_displacement) {
        const DisplacementCondition& d = displacements[index];
        m = displacement_matrix(coeffs, sources[s].source, d.point);
        w = d.weight;
        target = d.displacement;
      } else {
        const TractionCondition& t = tractions[index - displacements.size()];
        m = traction_map(kernel, sources[s].source, t.point, t.normal);
        w = traction_weight;
        target = t.traction;
      }
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
          const double f = scaled ? scaled_component(sources[s].force, k) : 1.0;
          block.rows[c][3 * s + k] = w * m(c, k) * f;
        }
      }
    }
    for (int c = 0; c < 3; ++c) block.rows[c][unknowns] = w * target[c];
  };

  const std::size_t conditions = displacements.size() + tractions.size();
  // One pass builds every row once and rotates it into R. Column norms of A equal those of R
  // (Q is orthogonal), so equilibrating R's columns afterwards is the same as equilibrating A's
  // first: the rank test and the condition number then do not depend on units (forces of 1e7
  // against weights of 1).
  StreamingQr qr(unknowns);
  RowBlock block;
  double rhs_norm = 0.0;
  for (std::size_t i = 0; i < conditions; ++i) {
    fill(i, block);
    for (auto& row : block.rows) {
      rhs_norm += row[unknowns] * row[unknowns];
      qr.add_row(row);
    }
  }
  rhs_norm = std::sqrt(rhs_norm);
  std::array<double, kMaxUnknowns> column_norm{};
  for (int j = 0; j < unknowns; ++j) {
    for (int i = 0; i <= j; ++i) column_norm[j] += qr.at(i, j) * qr.at(i, j);
    column_norm[j] = std::sqrt(column_norm[j]);
  }

  SmallMatrix r(unknowns, unknowns);
  SmallVector qtb(unknowns);
  for (int i = 0; i < unknowns; ++i) {
    qtb(i) = qr.at(i, unknowns);
    for (int j = 0; j < unknowns; ++j) {
      r(i, j) = j >= i && column_norm[j] > 0.0 ? qr.at(i, j) / column_norm[j] : 0.0;
    }
  }
  const Eigen::JacobiSVD<SmallMatrix> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const SmallVector sigma = svd.singularValues();
  const double sigma_max = sigma.size() > 0 ? sigma(0) : 0.0;
  if (!(sigma_max > 0.0) || !std::isfinite(sigma_max)) return report;

  const double cutoff = options_.rank_tolerance * sigma_max;
  std::size_t rank = 0;
  while (rank < static_cast<std::size_t>(sigma.size()) && sigma(static_cast<int>(rank)) > cutoff) ++rank;
  report.rank = rank;
  const double sigma_min = sigma(sigma.size() - 1);
  report.condition = sigma_min > 0.0 ? sigma_max / sigma_min : std::numeric_limits<double>::infinity();
  report.effective_condition = sigma_max / sigma(static_cast<int>(rank) - 1);

  // Minimum-norm solution over the kept singular values; past max_condition, Tikhonov filter
  // factors sigma / (sigma^2 + mu^2) damp the weakest directions instead of amplifying noise.
  report.damped = report.effective_condition > options_.max_condition;
  const double mu = sigma_max / std::sqrt(options_.max_condition);
  const SmallVector utb = svd.matrixU().transpose() * qtb;
  SmallVector scaled_solution = SmallVector::Zero(unknowns);
  for (std::size_t k = 0; k < rank; ++k) {
    const double s = sigma(static_cast<int>(k));
    const double inverse = report.damped ? s / (s * s + mu * mu) : 1.0 / s;
    scaled_solution += svd.matrixV().col(static_cast<int>(k)) * (utb(static_cast<int>(k)) * inverse);
  }

  for (std::size_t s = 0; s < n; ++s) {
    for (int k = 0; k < 3; ++k) {
      const int j = static_cast<int>(3 * s) + k;
      const double alpha = column_norm[j] > 0.0 ? scaled_solution(j) / column_norm[j] : 0.0;
      weights[s][k] = alpha;
      effective[s][k] = scaled ? alpha * scaled_component(sources[s].force, k) : alpha;
    }
  }

  // With every direction kept and no damping, the augmented factor's last diagonal is the
  // residual of the least-squares fit. Otherwise it is evaluated on the rows themselves, a
  // second pass, so it is true for truncated and damped solutions too.
  double residual2 = qr.at(unknowns, unknowns) * qr.at(unknowns, unknowns);
  const bool exact_fit = rank == static_cast<std::size_t>(unknowns) && !report.damped;
  if (!exact_fit) residual2 = 0.0;
  for (std::size_t i = 0; i < conditions && !exact_fit; ++i) {
    fill(i, block);
    for (const auto& row : block.rows) {
      double ax = -row[unknowns];
      for (std::size_t s = 0; s < n; ++s)
        for (int k = 0; k < 3; ++k) ax += row[3 * s + k] * weights[s][k];
      residual2 += ax * ax;
    }
  }
  report.residual = std::sqrt(residual2);
  report.relative_residual = rhs_norm > 0.0 ? report.residual / rhs_norm : 0.0;
  report.ok = std::isfinite(report.residual);
  if (!report.ok) {
    for (std::size_t s = 0; s < n; ++s) weights[s] = effective[s] = Vec3{};
  }
  return report;
}

}  // namespace sculpt::deform
