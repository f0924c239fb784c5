#include "repeat_timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace sculpt::tools {

RepeatTimes summarise_repeats(std::vector<double> times_ms) {
  RepeatTimes t;
  if (times_ms.empty()) return t;
  t.cold_ms = times_ms.front();
  std::sort(times_ms.begin(), times_ms.end());
  const std::size_t n = times_ms.size();
  t.median_ms = n % 2 == 1 ? times_ms[n / 2] : 0.5 * (times_ms[n / 2 - 1] + times_ms[n / 2]);
  // Nearest rank: the smallest time at least 99 % of the runs do not exceed.
  const auto rank = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(n)));
  t.p99_ms = times_ms[std::max<std::size_t>(rank, 1) - 1];
  return t;
}

}  // namespace sculpt::tools
