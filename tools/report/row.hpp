#pragma once
// One line of the report: an approximation, how long its frames took and how far its result
// was from the exact computation.

#include <cstdint>
#include <string>
#include <vector>

#include "sculpt/deform/deformer.hpp"

namespace sculpt::tools::report {

enum class RowKind {
  kExact,     ///< the reference itself (its error is zero by definition)
  kPerFrame,  ///< each frame started from the exact state, one frame compared
  kSession,   ///< a whole session (a reduced set transferred), compared at its end
  kTimeOnly,  ///< cannot change the result: measured for its time only
};

const char* kind_name(RowKind kind);

struct Row {
  std::string name;
  std::string group;  ///< "precision", "region", "kernel", "normals", "reduced set", ...
  RowKind kind = RowKind::kPerFrame;
  std::size_t frames = 0;   ///< frames timed
  double median_ms = 0.0;   ///< frame time median
  double p99_ms = 0.0;      ///< frame time 99th percentile
  double mean_error = 0.0;  ///< mean point error / bounding-box diagonal (mean over frames)
  double max_error = 0.0;   ///< largest point error / bounding-box diagonal
  double max_normal_error_deg = 0.0;
  double max_displacement = 0.0;   ///< the exact frames' largest displacement / bounding-box diagonal
  std::uint32_t probe_inside = 0;  ///< probe-frames ending more than Δd across the surface
  deform::GuardCounts guards;
  bool pareto = false;  ///< on the front of (median time, mean error)
};

/// A row with its labels and nothing measured yet.
Row labelled(std::string name, std::string group, RowKind kind);

/// Median and 99th percentile (nearest rank) of `ns`, in ms; zeros when empty.
void set_times(Row& row, std::vector<double> ns);

}  // namespace sculpt::tools::report
