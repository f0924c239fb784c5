#pragma once
// Runs one case: the stroke itself, judged frame by frame, then the same stroke again with G
// times 1e4, in a scaled frame and in a rotated and shifted frame, each compared with the first.

#include <optional>
#include <string>
#include <vector>

#include "check_cases.hpp"
#include "stroke_runner.hpp"

namespace sculpt::tools::check {

/// Worst relative deviations allowed. Single frames: float precision of one pass over float
/// positions. Strokes: the same per frame, grown by a few hundred frames of float round-off.
struct Tolerances {
  double single_frame = 1e-4;
  double stroke = 1e-3;
  double max_displacement_ratio = 3.0;  ///< strokes only
};

struct CaseResult {
  const CaseSpec* spec = nullptr;
  Metrics metrics;
  std::optional<double> g_deviation, scale_deviation, rigid_deviation;
  double tolerance = 0.0;
  std::vector<std::string> failures;  ///< empty: passed
  double seconds = 0.0;
};

CaseResult run_case(const CaseSpec& spec, const Tolerances& tolerances);

}  // namespace sculpt::tools::check
