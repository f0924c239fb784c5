#pragma once
// Frame times of a repeated run (`sculpt deform --repeat N`): the first, cold frame apart from
// the typical and the worst of all N, since one frame says little on a shared machine.

#include <vector>

namespace sculpt::tools {

struct RepeatTimes {
  double cold_ms = 0.0;    ///< the first run: caches and pages cold, as a script's one frame is
  double median_ms = 0.0;  ///< over all runs
  double p99_ms = 0.0;     ///< over all runs, nearest rank (the largest for fewer than 100)
};

/// `times_ms` in run order, at least one. Takes a copy: the order is kept for the caller.
RepeatTimes summarise_repeats(std::vector<double> times_ms);

}  // namespace sculpt::tools
