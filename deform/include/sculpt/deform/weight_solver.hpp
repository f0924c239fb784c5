#pragma once
// Least-squares weights that make the superposed Kelvin sources meet the boundary conditions
// (MATH.md §3).

#include <cstddef>
#include <span>

#include "sculpt/deform/displacement_field.hpp"
#include "sculpt/deform/kernel.hpp"

namespace sculpt::deform {

/// Which unknowns the solve finds (MATH.md §3).
enum class WeightForm {
  kForce,  ///< thesis chapter 3: the weights alpha_i are the effective force of source i
  kScale,  ///< thesis chapter 4: the weights scale the components of F_i, f_i = (F_ik alpha_ik)_k
};

/// A prescribed displacement u0 at a point; `weight` scales its three rows.
struct DisplacementCondition {
  Vec3 point;
  Vec3 displacement;
  double weight = 1.0;
};

/// A prescribed traction t0 on the surface through `point` with unit `normal`.
struct TractionCondition {
  Vec3 point;
  Vec3 normal;
  Vec3 traction;
};

/// A source and the force F computed from penetration (used by the kScale form only).
struct SourceSetup {
  Vec3 source;
  Vec3 force;
};

struct SolverOptions {
  /// kForce by default: its effective forces are continuous in the input and turn with the
  /// model (README "Weight forms"); kScale is kept for fidelity to the thesis's chapter 4.
  WeightForm form = WeightForm::kForce;
  /// eps_f of thesis eq. 13: traction rows are weighted by sqrt(beta), beta = eps_f / E^2.
  double traction_eps = 1.0;
  /// Singular values below this fraction of the largest are treated as zero (rank deficiency:
  /// a zero force component, duplicate conditions): numerically zero in double.
  double rank_tolerance = 1e-13;
  /// Past this condition number (after truncation) the solve falls back to Tikhonov damping.
  /// Must stay below 1 / rank_tolerance, or truncation would always act first and damping never.
  double max_condition = 1e8;
  /// kScale: a component of F smaller than this fraction of |F| counts as zero, so float noise
  /// (F_x = -1.2e-8 on |F| = 0.01, where it is 0 before a translation) pins it like an exact
  /// zero does: about 100 float epsilons.
  double zero_component = 1e-5;

  /// Throws std::invalid_argument naming the bad option.
  void validate() const;
};

/// What every solve reports.
struct SolveReport {
  bool ok = false;                 ///< false when there was nothing to solve or no finite solution
  std::size_t rows = 0;            ///< stacked rows, 3 (m_D + m_F)
  std::size_t unknowns = 0;        ///< 3 n
  std::size_t rank = 0;            ///< numerical rank after truncation
  double residual = 0.0;           ///< || A alpha - b || over the weighted rows
  double relative_residual = 0.0;  ///< residual / ||b|| (0 when b = 0)
  double condition = 0.0;          ///< sigma_max / sigma_min of the column-equilibrated system (inf if rank-deficient)
  double effective_condition = 0.0;  ///< sigma_max / smallest kept sigma
  bool damped = false;               ///< Tikhonov fallback used
};

/// Solves for the weights: rows are reduced, 96 at a time, into a small upper-triangular factor
/// R. Where the column-equilibrated system is well conditioned (condition <= 1e3, every frame
/// measured: 1.2 to 2.3), R comes from the Gram matrix of a tall system by Cholesky, and the
/// weights by back substitution, with the condition number from the eigenvalues of R^T R.
/// Anything else is reduced by blocked Householder QR, without forming the normal equations,
/// and R's SVD (one-sided Jacobi) gives the rank, the condition number and the minimum-norm or
/// damped solution. Working storage is fixed-size, so solve() neither allocates nor throws,
/// whatever the number of rows.
class WeightSolver {
 public:
  explicit WeightSolver(const SolverOptions& options = {}) : options_(options) { options_.validate(); }

  /// Writes the effective force of each source to `effective` and the raw weights to
  /// `weights` (both sized like `sources`, at most kMaxSources).
  SolveReport solve(const Kernel& kernel, std::span<const SourceSetup> sources,
                    std::span<const DisplacementCondition> displacements, std::span<const TractionCondition> tractions,
                    std::span<Vec3> weights, std::span<Vec3> effective) const noexcept;

  const SolverOptions& options() const { return options_; }

 private:
  SolverOptions options_;
};

}  // namespace sculpt::deform
