#pragma once
// The yardsticks every frame is divided by, measured in the same run: the bare Kelvin pass (the
// displacement of five point forces summed at every float point, nothing else), written here to
// run at the reference kernel's speed (../shared/bench/), and one streaming pass over the
// positions (read and write each once), the memory bound below any per-point work.

#include <cstddef>
#include <vector>

namespace sculpt::bench {

/// Positions as the project stores them: float, structure of arrays.
struct FloatPoints {
  std::vector<float> x, y, z;
  std::size_t size() const { return x.size(); }
};

/// `n` points spread over the unit sphere (a golden-angle spiral: deterministic, no clumps).
FloatPoints sphere_points(std::size_t n);

/// Five point forces just outside the unit sphere, small enough that a pass barely moves it.
struct FiveForces {
  static constexpr int kCount = 5;
  float px[kCount], py[kCount], pz[kCount];  // where each force acts
  float fx[kCount], fy[kCount], fz[kCount];  // each force times c = 1 / (16 pi G (1 - nu))
  float three_minus_four_nu;
};
FiveForces five_forces();

/// u(q) = sum_f c/R [(3 - 4 nu) F + r (r . F) / R^2] added to every point (MATH.md §1), once.
void bare_kelvin_pass(FloatPoints& points, const FiveForces& forces);

/// Every coordinate read and written once (scaled by a number that keeps it finite).
void stream_pass(FloatPoints& points);

}  // namespace sculpt::bench
