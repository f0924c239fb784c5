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
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <limits>

namespace sculpt::deform {
namespace {

constexpr int kMaxUnknowns = 3 * static_cast<int>(kMaxSources);
using SquareRows = std::array<std::array<double, kMaxUnknowns>, kMaxUnknowns>;

// The upper-triangular factor R of [A | b], built from blocks of rows with Householder
// reflections: after all rows, R(0:n, 0:n) is A's R, R(0:n, n) is Q^T b and |R(n, n)| the
// residual of the unconstrained fit. A block of kBlockRows rows is folded into R column by
// column; each column costs one reflector (one square root and one division for the whole block,
// where a Givens rotation per row took one of each per row and column) and the block's updates
// run over contiguous columns of fixed length, so they vectorise. Tall systems may take the
// Gram route instead (accumulate() and cholesky(), the same R when the system is well
// conditioned, checked before it is kept). The whole stays (n + 1)^2 doubles, one block and
// the Gram route's partial sums.
constexpr int kBlockConditions = 32;
constexpr int kBlockRows = 3 * kBlockConditions;
// From this many conditions on, the Gram route is tried first (below it the reflections cost
// a few microseconds at most).
constexpr std::size_t kGramMinConditions = 2 * kBlockConditions;
// The Gram route's sums: kLanes partial sums per product (one AVX-512 register of doubles;
// GCC's vector extension splits it where registers are narrower).
constexpr int kLanes = 8;
static_assert(kBlockRows % kLanes == 0);
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));
// Built without AVX-512 (the sanitizer builds), GCC warns that passing such a vector by value
// is done differently than with it. Every function taking or returning one is internal to this
// file, compiled with one set of flags, so the difference can never meet itself.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

inline Lanes load_lanes(const double* from) {
  Lanes v;
  std::memcpy(&v, from, sizeof v);
  return v;
}

// Fixed-length columns: Eigen vectorises their dot products and updates (its reductions sum in
// packets, which plain loops may not do without reassociation).
using BlockColumn = Eigen::Matrix<double, kBlockRows, 1>;

inline double dot_column(const BlockColumn& a, const BlockColumn& b) { return a.dot(b); }

// |v| without overflow or underflow: the plain sum of squares where it stays well inside the
// double range (every real block here), the largest magnitude factored out otherwise.
inline double column_length(const BlockColumn& v) {
  constexpr double kSafeMax = 0x1p900, kSafeMin = 0x1p-900;
  const double plain = dot_column(v, v);
  if (plain < kSafeMax && plain > kSafeMin) return std::sqrt(plain);
  if (std::isnan(plain)) return plain;  // a NaN entry: let it reach R, so the solve reports it
  double big = 0.0;
  for (double x : v) big = std::max(big, std::abs(x));
  if (big == 0.0 || !std::isfinite(big)) return big;
  return big * (v / big).norm();
}

// sqrt(a^2 + b^2) for two non-negative lengths, with the same guard.
inline double pair_length(double a, double b) {
  constexpr double kSafeMax = 0x1p450, kSafeMin = 0x1p-450;
  const double big = std::max(a, b), small = std::min(a, b);
  if (big < kSafeMax && small > kSafeMin) return std::sqrt(a * a + b * b);
  if (big == 0.0) return 0.0;
  const double ratio = small / big;
  return big * std::sqrt(1.0 + ratio * ratio);
}

class BlockedQr {
 public:
  // Only the n + 1 columns (and R's n + 1 rows) a solve of n unknowns uses are cleared: zeroing
  // all kMaxUnknowns + 1 columns of a block was 24 KB per solve, most of a small solve's memset.
  explicit BlockedQr(int unknowns) : n_(unknowns) { reset(); }

  void reset() {
    for (int i = 0; i <= n_; ++i) std::fill_n(r_[static_cast<std::size_t>(i)].begin(), n_ + 1, 0.0);
    for (int j = 0; j <= n_; ++j) block_[static_cast<std::size_t>(j)].setZero();
    std::fill_n(partial_.begin(), (n_ + 1) * (n_ + 2) / 2, Lanes{});
    residual_trusted_ = true;
  }

  /// Column j (0..n, n the right-hand side) of the pending block; rows not written stay zero.
  BlockColumn& column(int j) { return block_[static_cast<std::size_t>(j)]; }

  /// Folds the pending block into R and zeroes it for the next one. Zero rows change nothing.
  void fold() {
    for (int k = 0; k <= n_; ++k) {
      BlockColumn& vk = block_[static_cast<std::size_t>(k)];
      const double below = column_length(vk);
      if (below == 0.0) continue;
      // The reflector H = I - tau [1; v] [1; v]^T maps (R(k,k), vk) onto (beta, 0) (LAPACK's
      // dlarfg): beta takes the sign opposite to alpha, so alpha - beta never cancels.
      const double alpha = r_[k][k];
      const double beta = -std::copysign(pair_length(std::abs(alpha), below), alpha);
      const double tau = (beta - alpha) / beta;
      const double inv = 1.0 / (alpha - beta);  // v = vk * inv
      // All of the column's dot products first, then all updates: each loop's iterations are
      // independent, so the reductions' latencies overlap instead of queueing behind updates.
      std::array<double, kMaxUnknowns + 1> w;
      for (int j = k + 1; j <= n_; ++j) w[j] = tau * (r_[k][j] + inv * dot_column(vk, block_[j]));
      for (int j = k + 1; j <= n_; ++j) {
        r_[k][j] -= w[j];
        block_[j] -= (w[j] * inv) * vk;
      }
      r_[k][k] = beta;
      vk.setZero();
    }
  }

  /// The other route to the same R, for tall well-conditioned systems: add the pending block's
  /// products to the Gram matrix of [A | b], kept in R's upper triangle (136 dot products of a
  /// block's columns at n = 15, where folding it took a reflector per column, each a chain of
  /// a reduction, a square root and a division). A fill writes only its `count` conditions, so
  /// a partial block's other rows are cleared first; the rest are overwritten by the next fill.
  void accumulate(std::size_t count) {
    if (count < static_cast<std::size_t>(kBlockConditions)) {
      for (int j = 0; j <= n_; ++j) {
        for (int c = 0; c < 3; ++c)
          block_[static_cast<std::size_t>(j)]
              .segment(c * kBlockConditions + static_cast<Eigen::Index>(count),
                       kBlockConditions - static_cast<Eigen::Index>(count))
              .setZero();
      }
    }
    // Each product is summed lane-wise into its own vector of partial sums and reduced across
    // lanes once, in cholesky(): a horizontal sum per product and block was half the time.
    // Four columns j at a time against one column i: four independent chains of fused
    // multiply-adds (one chain per product waited on its own latency) that share i's loads.
    // The sums are GCC vector values so that they stay in registers (as arrays, GCC kept
    // them on the stack and the stores cost more than the arithmetic).
    std::size_t product = 0;
    for (int i = 0; i <= n_; ++i) {
      const double* a = block_[static_cast<std::size_t>(i)].data();
      int j = i;
      for (; j + 4 <= n_ + 1; j += 4) {
        const double* b0 = block_[static_cast<std::size_t>(j)].data();
        const double* b1 = block_[static_cast<std::size_t>(j + 1)].data();
        const double* b2 = block_[static_cast<std::size_t>(j + 2)].data();
        const double* b3 = block_[static_cast<std::size_t>(j + 3)].data();
        Lanes s0{}, s1{}, s2{}, s3{};
        for (int row = 0; row < kBlockRows; row += kLanes) {
          const Lanes x = load_lanes(a + row);
          s0 += x * load_lanes(b0 + row);
          s1 += x * load_lanes(b1 + row);
          s2 += x * load_lanes(b2 + row);
          s3 += x * load_lanes(b3 + row);
        }
        partial_[product++] += s0;
        partial_[product++] += s1;
        partial_[product++] += s2;
        partial_[product++] += s3;
      }
      for (; j <= n_; ++j) {
        const double* b = block_[static_cast<std::size_t>(j)].data();
        Lanes sum{};
        for (int row = 0; row < kBlockRows; row += kLanes) sum += load_lanes(a + row) * load_lanes(b + row);
        partial_[product++] += sum;
      }
    }
  }

  /// Replaces the accumulated Gram matrix by its Cholesky factor: R of [A | b] up to the signs of
  /// its rows (A^T A = R^T R either way). False, leaving a factor to be discarded, when a pivot of
  /// A's columns is not positive and finite. The last pivot, the residual's square, is the
  /// difference |b|^2 - |Q^T b|^2 and cancels when the fit is close; it is floored at zero, and
  /// `residual_trusted()` says whether it kept enough digits.
  bool cholesky() {
    std::size_t product = 0;
    for (int i = 0; i <= n_; ++i) {
      for (int j = i; j <= n_; ++j) {
        const Lanes& partial = partial_[product++];
        double sum = 0.0;
        for (int l = 0; l < kLanes; ++l) sum += partial[l];
        r_[i][j] = sum;
      }
    }
    const double rhs_squared = r_[n_][n_];
    for (int k = 0; k <= n_; ++k) {
      double pivot = r_[k][k];
      for (int i = 0; i < k; ++i) pivot -= r_[i][k] * r_[i][k];
      if (k == n_) {
        // A relative residual above 1e-3: the cancellation costs at most 6 of 16 digits.
        residual_trusted_ = pivot >= 1e-6 * rhs_squared;
        r_[k][k] = std::sqrt(std::max(pivot, 0.0));
        return true;
      }
      if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
      const double diagonal = std::sqrt(pivot);
      r_[k][k] = diagonal;
      for (int j = k + 1; j <= n_; ++j) {
        double sum = r_[k][j];
        for (int i = 0; i < k; ++i) sum -= r_[i][k] * r_[i][j];
        r_[k][j] = sum / diagonal;
      }
    }
    return true;
  }

  /// False only after cholesky() found the residual's pivot cancelled.
  bool residual_trusted() const { return residual_trusted_; }

  double at(int i, int j) const { return r_[i][j]; }

 private:
  int n_;
  bool residual_trusted_ = true;
  // The Gram route's products of columns i <= j, packed row by row, kLanes partial sums each.
  std::array<Lanes, (kMaxUnknowns + 1) * (kMaxUnknowns + 2) / 2> partial_;
  std::array<std::array<double, kMaxUnknowns + 1>, kMaxUnknowns + 1> r_;
  std::array<BlockColumn, kMaxUnknowns + 1> block_;
};

// The SVD of the equilibrated n x n factor R by one-sided (Hestenes) Jacobi on its rows, then
// the rank, the condition numbers and the minimum-norm (or damped) solution of R x = qtb.
// The columns of B = R^T are rotated pairwise until orthogonal, B W = Z, so that
// R = W diag(|z_k|) (z_k / |z_k|)^T: W holds the left singular vectors and the normalised z_k the
// right ones. One-sided Jacobi finds small singular values to high relative accuracy (it never
// forms R^T R), and its columns are contiguous vectors of fixed length L >= n, so each pair's
// dot products and rotations vectorise; Eigen's two-sided JacobiSVD took 0.1 ms for 15 x 15.
template <int L>
bool svd_solve(int n, const SquareRows& r, const std::array<double, kMaxUnknowns>& qtb, const SolverOptions& options,
               SolveReport& report, std::array<double, kMaxUnknowns>& x) {
  using Column = Eigen::Matrix<double, L, 1>;
  std::array<Column, L> b, w;
  std::array<double, L> squared{};
  for (int i = 0; i < n; ++i) {
    b[i].setZero();
    w[i].setZero();
    w[i][i] = 1.0;
    for (int j = i; j < n; ++j) b[i][j] = r[i][j];
  }
  // Converged when every pair's cosine is below n ulps (LAPACK's dgesvj uses sqrt(m) ulps).
  const double tolerance = n * std::numeric_limits<double>::epsilon();
  // A sweep visits every pair once in a round-robin (parallel) order: the n columns, and a bye
  // when n is odd, sit at `seats` places; each step pairs place k with place seats-1-k, then
  // every column but the first moves one place along. A step's pairs share no column, so their
  // rotations are independent and overlap in the pipeline; in the cyclic order each rotation
  // waited for the one before it, a square root and two divisions deep, and that chain was most
  // of a small solve.
  const int seats = n + (n & 1);
  std::array<int, L> seat{};
  for (int i = 0; i < seats; ++i) seat[i] = i;
  constexpr int kMaxSweeps = 40;
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    for (int i = 0; i < n; ++i) squared[i] = b[i].squaredNorm();
    bool rotated = false;
    for (int step = 0; step + 1 < seats; ++step) {
      for (int k = 0; k < seats / 2; ++k) {
        const int p = std::min(seat[k], seat[seats - 1 - k]), q = std::max(seat[k], seat[seats - 1 - k]);
        if (q >= n) continue;  // the bye
        const double alpha = squared[p], beta = squared[q];
        const double gamma = b[p].dot(b[q]);
        if (!(std::abs(gamma) > tolerance * std::sqrt(alpha * beta))) continue;
        rotated = true;
        // The rotation that makes columns p and q orthogonal (Rutishauser's formulas).
        const double zeta = (beta - alpha) / (2.0 * gamma);
        const double t = std::copysign(1.0, zeta) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
        const double c = 1.0 / std::sqrt(1.0 + t * t), s = c * t;
        const Column bp = b[p];
        b[p] = c * bp - s * b[q];
        b[q] = s * bp + c * b[q];
        const Column wp = w[p];
        w[p] = c * wp - s * w[q];
        w[q] = s * wp + c * w[q];
        squared[p] = std::max(0.0, alpha - t * gamma);
        squared[q] = beta + t * gamma;
      }
      const int moving = seat[seats - 1];
      for (int i = seats - 1; i > 1; --i) seat[i] = seat[i - 1];
      seat[1] = moving;
    }
    if (!rotated) break;
  }

  std::array<double, L> sigma{};
  std::array<int, L> order{};
  for (int i = 0; i < n; ++i) {
    sigma[i] = b[i].norm();
    order[i] = i;
  }
  // Descending singular values (insertion sort: n <= 30; NaN, if any, stays put and fails below).
  for (int i = 1; i < n; ++i) {
    for (int k = i; k > 0 && sigma[order[k - 1]] < sigma[order[k]]; --k) std::swap(order[k - 1], order[k]);
  }
  auto singular = [&](int k) { return sigma[order[k]]; };
  const double sigma_max = singular(0);
  if (!(sigma_max > 0.0) || !std::isfinite(sigma_max)) return false;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(sigma[i])) return false;
  }

  const double cutoff = options.rank_tolerance * sigma_max;
  int rank = 0;
  while (rank < n && singular(rank) > cutoff) ++rank;
  report.rank = static_cast<std::size_t>(rank);
  const double sigma_min = singular(n - 1);
  report.condition = sigma_min > 0.0 ? sigma_max / sigma_min : std::numeric_limits<double>::infinity();
  report.effective_condition = sigma_max / singular(rank - 1);

  // Minimum-norm solution over the kept singular values; past max_condition, Tikhonov filter
  // factors sigma / (sigma^2 + mu^2) damp the weakest directions instead of amplifying noise.
  report.damped = report.effective_condition > options.max_condition;
  const double mu = sigma_max / std::sqrt(options.max_condition);
  Column y = Column::Zero();
  for (int i = 0; i < n; ++i) y[i] = qtb[i];
  Column solution = Column::Zero();
  for (int k = 0; k < rank; ++k) {
    const int i = order[k];
    const double s = sigma[i];
    const double inverse = report.damped ? s / (s * s + mu * mu) : 1.0 / s;
    // Left vector w_i, right vector b_i / s.
    solution += b[i] * (w[i].dot(y) * inverse / s);
  }
  for (int i = 0; i < n; ++i) x[i] = solution[i];
  return true;
}

// The smallest and the largest eigenvalue of the symmetric tridiagonal matrix with diagonal a
// and squared off-diagonal b2, by bisection on Sturm counts (the number of negative pivots of
// T - x I is the number of eigenvalues below x), eight shifts at a time for each end, so that
// each step narrows both brackets ninefold, to a relative 1e-10 of each end (below). Eigen's
// implicit QL for every eigenvalue took 2 to 6 us where only these two are needed. The two
// ends' counts are independent chains of divisions, so they overlap.
struct Extremes {
  double lowest, highest;
};

// Each end is wanted to this relative width of itself: the condition number the two give is then
// good to about 1e-10, where the report and its tests need 1e-6. A few ulps of the largest
// magnitude, the bound before, took a third more steps on a well-conditioned matrix.
constexpr double kEigenvalueRelativeTolerance = 1e-10;

Extremes extreme_eigenvalues(int n, const std::array<double, kMaxUnknowns>& a,
                             const std::array<double, kMaxUnknowns>& b2) noexcept {
  using Counts = std::int64_t __attribute__((vector_size(kLanes * sizeof(std::int64_t))));
  double low = std::numeric_limits<double>::infinity(), high = -low, largest_b2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double radius = (i > 0 ? std::sqrt(b2[i - 1]) : 0.0) + (i + 1 < n ? std::sqrt(b2[i]) : 0.0);
    low = std::min(low, a[i] - radius);
    high = std::max(high, a[i] + radius);
    if (i + 1 < n) largest_b2 = std::max(largest_b2, b2[i]);
  }
  // A NaN entry is skipped by the bounds above but not by the counts: refuse it here.
  bool finite = std::isfinite(low) && std::isfinite(high);
  for (int i = 0; i < n; ++i) finite = finite && std::isfinite(a[i]) && (i + 1 == n || std::isfinite(b2[i]));
  if (!finite) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  // LAPACK's dstebz: a pivot smaller than this is replaced by its negative, so no division by
  // zero, and the count stays that of a nearby matrix.
  const double pivot_floor = std::numeric_limits<double>::min() * std::max(1.0, largest_b2);
  // Never finer than a few ulps of the largest magnitude, which is all the entries carry (the
  // smallest end of a poorly conditioned matrix stops there; kEigenvalueRelativeTolerance).
  const double ulp_floor = 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(low), std::abs(high));
  // Negative counts of the eigenvalues below each lane's shift (a true comparison is -1).
  auto below = [&](const Lanes& x) {
    Lanes d = a[0] - x;
    Counts count = d < 0.0;
    for (int i = 1; i < n; ++i) {
      d = (d > -pivot_floor && d < pivot_floor) ? -pivot_floor : d;
      d = (a[i] - x) - b2[i - 1] / d;
      count += d < 0.0;
    }
    return count;
  };
  // A bracket [lo, hi] of the eigenvalue that is the `rank`-th from the bottom: it lies below
  // every shift with at least `rank` eigenvalues below it and above every other shift.
  struct Bracket {
    double lo, hi;
    std::int64_t rank;
    bool settled(double ulp_floor) const {
      return hi - lo <= std::max(ulp_floor, kEigenvalueRelativeTolerance * std::max(std::abs(lo), std::abs(hi)));
    }
    Lanes shifts() const {
      Lanes at;
      for (int l = 0; l < kLanes; ++l) at[l] = lo + (hi - lo) * (l + 1) / (kLanes + 1);
      return at;
    }
    void narrow(const Lanes& at, const Counts& negative_count) {
      double next_lo = lo, next_hi = hi;
      for (int l = kLanes - 1; l >= 0; --l) {
        if (-negative_count[l] < rank) {
          next_lo = at[l];
          break;
        }
        next_hi = at[l];
      }
      lo = next_lo;
      hi = next_hi;
    }
  };
  Bracket lowest{low, high, 1}, highest{low, high, n};
  for (int step = 0; step < 64 && !(lowest.settled(ulp_floor) && highest.settled(ulp_floor)); ++step) {
    const Lanes at_low = lowest.shifts(), at_high = highest.shifts();
    const Counts low_count = below(at_low), high_count = below(at_high);
    lowest.narrow(at_low, low_count);
    highest.narrow(at_high, high_count);
  }
  return {0.5 * (lowest.lo + lowest.hi), 0.5 * (highest.lo + highest.hi)};
}

// Past this condition number of the equilibrated factor the direct solve below hands over to
// the Jacobi SVD. Every frame of the benchmarks (sphere, bust, both dragons, one to five
// fingers, global and region) measured 1.2 to 2.3, so the limit leaves room for fingers far
// closer together; below it the eigenvalues of R^T R give sigma_min to a relative n eps
// kappa^2 <= 4e-9 (n <= 30), well inside what the report and its tests need (1e-6).
constexpr double kDirectConditionLimit = 1e3;

// The well-conditioned case without the SVD: the extreme singular values from the extreme
// eigenvalues of the n x n Gram matrix R^T R (Eigen's tridiagonal reduction, then bisection:
// 2 to 4 us where the Jacobi sweeps took 20 at n = 15), then R x = qtb by back substitution,
// which is the minimum-norm solution whenever R has full rank and no damping acts. Returns
// false, having written nothing, when any of that does not hold; the caller then runs the SVD.
bool direct_solve(int n, const SquareRows& r, const std::array<double, kMaxUnknowns>& qtb, const SolverOptions& options,
                  SolveReport& report, std::array<double, kMaxUnknowns>& x) {
  using Gram = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxUnknowns, kMaxUnknowns>;
  Gram gram(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      double sum = 0.0;
      for (int k = 0; k <= i; ++k) sum += r[k][i] * r[k][j];
      gram(i, j) = gram(j, i) = sum;
    }
  }
  const Eigen::Tridiagonalization<Gram> tridiagonal(gram);
  std::array<double, kMaxUnknowns> diagonal{}, off_squared{};
  for (int i = 0; i < n; ++i) diagonal[i] = tridiagonal.diagonal()(i);
  for (int i = 0; i + 1 < n; ++i) off_squared[i] = tridiagonal.subDiagonal()(i) * tridiagonal.subDiagonal()(i);
  const auto [lowest, highest] = extreme_eigenvalues(n, diagonal, off_squared);
  if (!(lowest > 0.0) || !std::isfinite(highest)) return false;
  const double condition = std::sqrt(highest / lowest);
  if (!(condition <= kDirectConditionLimit) || condition > options.max_condition ||
      !(1.0 / condition > options.rank_tolerance))
    return false;
  std::array<double, kMaxUnknowns> solution{};
  for (int i = n - 1; i >= 0; --i) {
    double sum = qtb[i];
    for (int j = i + 1; j < n; ++j) sum -= r[i][j] * solution[j];
    solution[i] = sum / r[i][i];
    if (!std::isfinite(solution[i])) return false;
  }
  report.rank = static_cast<std::size_t>(n);
  report.condition = report.effective_condition = condition;
  report.damped = false;
  x = solution;
  return true;
}

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

  // Each source's factor per force component: 1 in the force form, F_ik (or 0) in the scale
  // form, found once rather than per row.
  std::array<std::array<double, 3>, kMaxSources> factor{};
  for (std::size_t s = 0; s < n; ++s) {
    for (int k = 0; k < 3; ++k) factor[s][k] = scaled ? scaled_component(sources[s].force, k) : 1.0;
  }

  // Writes the weighted rows of conditions first..first+count (displacements first, then
  // tractions) into a block's columns: row c kBlockConditions + q is component c of condition
  // first + q (components apart, so that a fill's stores run along contiguous rows; the order of
  // rows does not change R, and a block's layout does not depend on how full it is), and column 3 s + k the coefficient of unknown (s, k), column `unknowns`
  // the target.
  auto fill_general = [&](std::size_t first, std::size_t count, BlockedQr& qr) {
    for (std::size_t q = 0; q < count; ++q) {
      const std::size_t index = first + q;
      const bool is_displacement = index < displacements.size();
      double w = 1.0;
      Vec3 target;
      if (is_displacement) {
        w = displacements[index].weight;
        target = displacements[index].displacement;
      } else {
        w = traction_weight;
        target = tractions[index - displacements.size()].traction;
      }
      for (std::size_t s = 0; s < n; ++s) {
        Mat3 m;  // m(c, k): component c of the row quantity per unit force component k
        if (is_displacement) {
          m = displacement_matrix(coeffs, sources[s].source, displacements[index].point);
        } else {
          const TractionCondition& t = tractions[index - displacements.size()];
          m = traction_map(kernel, sources[s].source, t.point, t.normal);
        }
        for (int k = 0; k < 3; ++k) {
          const double f = w * factor[s][k];
          BlockColumn& col = qr.column(static_cast<int>(3 * s) + k);
          for (int c = 0; c < 3; ++c)
            col[static_cast<Eigen::Index>(static_cast<std::size_t>(c) * kBlockConditions + q)] = m(c, k) * f;
        }
      }
      BlockColumn& rhs = qr.column(unknowns);
      for (int c = 0; c < 3; ++c)
        rhs[static_cast<Eigen::Index>(static_cast<std::size_t>(c) * kBlockConditions + q)] = w * target[c];
    }
  };
  // The same for a block of displacement conditions only (every row of a region's band), one
  // source at a time over the block's points, so the square roots and divisions run as vector
  // instructions. The arithmetic is displacement_matrix()'s, operation for operation, so the
  // rows are the same bits as fill_general()'s (tested).
  auto fill_displacements = [&](std::size_t first, std::size_t count, BlockedQr& qr) {
    std::array<double, kBlockConditions> px{}, py{}, pz{}, weight{}, rx{}, ry{}, rz{}, diag{}, g{};
    for (std::size_t q = 0; q < count; ++q) {
      const DisplacementCondition& d = displacements[first + q];
      px[q] = d.point.x;
      py[q] = d.point.y;
      pz[q] = d.point.z;
      weight[q] = d.weight;
      BlockColumn& rhs = qr.column(unknowns);
      for (int c = 0; c < 3; ++c)
        rhs[static_cast<Eigen::Index>(static_cast<std::size_t>(c) * kBlockConditions + q)] =
            d.weight * d.displacement[c];
    }
    for (std::size_t s = 0; s < n; ++s) {
      const Vec3 p = sources[s].source;
      for (std::size_t q = 0; q < count; ++q) {
        rx[q] = px[q] - p.x;
        ry[q] = py[q] - p.y;
        rz[q] = pz[q] - p.z;
        const double r2 = rx[q] * rx[q] + ry[q] * ry[q] + rz[q] * rz[q] + coeffs.eps_squared;
        const double inv = 1.0 / std::sqrt(r2);
        const double inv3 = inv / r2;
        diag[q] = coeffs.alpha * inv + coeffs.beta * inv3;
        g[q] = coeffs.gamma * inv3;
      }
      for (int k = 0; k < 3; ++k) {
        const std::array<double, kBlockConditions>& rk = k == 0 ? rx : (k == 1 ? ry : rz);
        BlockColumn& col = qr.column(static_cast<int>(3 * s) + k);
        double* x = col.data();
        double* y = x + kBlockConditions;
        double* z = y + kBlockConditions;
        // One loop per component: with the three stores in one loop the compiler cannot rule
        // out that x, y and z overlap (it does not know count <= 32) and kept it scalar.
        const double fk = factor[s][k];
        for (std::size_t q = 0; q < count; ++q)
          x[q] = ((k == 0 ? diag[q] : 0.0) + g[q] * rx[q] * rk[q]) * (weight[q] * fk);
        for (std::size_t q = 0; q < count; ++q)
          y[q] = ((k == 1 ? diag[q] : 0.0) + g[q] * ry[q] * rk[q]) * (weight[q] * fk);
        for (std::size_t q = 0; q < count; ++q)
          z[q] = ((k == 2 ? diag[q] : 0.0) + g[q] * rz[q] * rk[q]) * (weight[q] * fk);
      }
    }
  };
  auto fill = [&](std::size_t first, std::size_t count, BlockedQr& qr) {
    if (first + count <= displacements.size()) {
      fill_displacements(first, count, qr);
    } else {
      fill_general(first, count, qr);
    }
  };

  const std::size_t conditions = displacements.size() + tractions.size();
  // One pass builds every row once and reduces it into R, a block at a time: by the Gram
  // matrix and its Cholesky factor when the system is tall enough for that to pay, and by
  // Householder reflections otherwise or when the Cholesky route cannot vouch for its result.
  // Column norms of A equal those of R (Q is orthogonal), so equilibrating R's columns
  // afterwards is the same as equilibrating A's first: the rank test and the condition number
  // then do not depend on units (forces of 1e7 against weights of 1).
  BlockedQr qr(unknowns);
  double rhs_norm = 0.0;
  auto reduce_rows = [&](bool gram) {
    rhs_norm = 0.0;
    for (std::size_t first = 0; first < conditions; first += kBlockConditions) {
      const std::size_t count = std::min<std::size_t>(kBlockConditions, conditions - first);
      fill(first, count, qr);
      if (gram) {
        qr.accumulate(count);
      } else {
        rhs_norm += dot_column(qr.column(unknowns), qr.column(unknowns));
        qr.fold();
      }
    }
    if (gram) rhs_norm = qr.at(unknowns, unknowns);
    rhs_norm = std::sqrt(rhs_norm);
    return !gram || qr.cholesky();
  };

  std::array<double, kMaxUnknowns> column_norm{};
  SquareRows r{};
  std::array<double, kMaxUnknowns> qtb{};
  auto equilibrate = [&] {
    for (int j = 0; j < unknowns; ++j) {
      column_norm[j] = 0.0;
      for (int i = 0; i <= j; ++i) column_norm[j] += qr.at(i, j) * qr.at(i, j);
      column_norm[j] = std::sqrt(column_norm[j]);
    }
    // The equilibrated factor, row by row (only its upper triangle is non-zero).
    for (int i = 0; i < unknowns; ++i) {
      qtb[i] = qr.at(i, unknowns);
      for (int j = i; j < unknowns; ++j) r[i][j] = column_norm[j] > 0.0 ? qr.at(i, j) / column_norm[j] : 0.0;
    }
  };
  std::array<double, kMaxUnknowns> scaled_solution{};
  auto svd = [&] {
    return unknowns <= 8    ? svd_solve<8>(unknowns, r, qtb, options_, report, scaled_solution)
           : unknowns <= 16 ? svd_solve<16>(unknowns, r, qtb, options_, report, scaled_solution)
                            : svd_solve<32>(unknowns, r, qtb, options_, report, scaled_solution);
  };

  // The Gram matrix squares the condition number, so its R is kept only where the direct
  // solve accepts it (equilibrated condition <= 1e3: R's relative error stays near 1e-10);
  // anything else is factored again by reflections and may go on to the SVD.
  bool solved = false;
  if (conditions >= kGramMinConditions && reduce_rows(true)) {
    equilibrate();
    solved = direct_solve(unknowns, r, qtb, options_, report, scaled_solution);
    if (!solved) qr.reset();
  }
  if (!solved) {
    reduce_rows(false);
    equilibrate();
    solved = direct_solve(unknowns, r, qtb, options_, report, scaled_solution) || svd();
  }
  if (!solved) return report;
  const std::size_t rank = report.rank;

  for (std::size_t s = 0; s < n; ++s) {
    for (int k = 0; k < 3; ++k) {
      const int j = static_cast<int>(3 * s) + k;
      const double alpha = column_norm[j] > 0.0 ? scaled_solution[j] / column_norm[j] : 0.0;
      weights[s][k] = alpha;
      effective[s][k] = scaled ? alpha * scaled_component(sources[s].force, k) : alpha;
    }
  }

  // With every direction kept and no damping, the augmented factor's last diagonal is the
  // residual of the least-squares fit. Otherwise (or when the Gram route's last pivot cancelled)
  // it is evaluated on the rows themselves, a second pass, so it is true for truncated and
  // damped solutions too.
  double residual2 = qr.at(unknowns, unknowns) * qr.at(unknowns, unknowns);
  const bool exact_fit = rank == static_cast<std::size_t>(unknowns) && !report.damped && qr.residual_trusted();
  if (!exact_fit) residual2 = 0.0;
  for (std::size_t first = 0; first < conditions && !exact_fit; first += kBlockConditions) {
    const std::size_t count = std::min<std::size_t>(kBlockConditions, conditions - first);
    BlockedQr rows(unknowns);  // only its block is used: a scratch for the same rows
    fill(first, count, rows);
    for (Eigen::Index i = 0; i < kBlockRows; ++i) {  // rows no condition wrote are zero
      double ax = -rows.column(unknowns)[i];
      for (std::size_t s = 0; s < n; ++s)
        for (int k = 0; k < 3; ++k) ax += rows.column(static_cast<int>(3 * s) + k)[i] * weights[s][k];
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
