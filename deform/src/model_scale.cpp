#include "sculpt/deform/model_scale.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sculpt::deform {

double mean_spacing(const PointModel& model, const PointIndex& index, std::size_t samples) {
  const std::size_t n = model.size();
  if (n < 2 || samples == 0) return 0.0;
  std::vector<std::uint32_t> neighbours;
  std::vector<double> squared;
  double sum = 0.0;
  std::size_t count = 0;
  const std::size_t step = std::max<std::size_t>(1, n / samples);
  for (std::size_t i = 0; i < n; i += step) {
    index.k_nearest(model.position(i), 2, neighbours, squared);
    if (squared.size() == 2) {
      sum += std::sqrt(squared[1]);
      ++count;
    }
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace sculpt::deform
