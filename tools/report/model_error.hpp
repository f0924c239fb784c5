#pragma once
// How far a float result lies from the exact state: the thesis's measure (point distance over
// the bounding-box diagonal) and the largest angle between corresponding normals.

#include "exact_state.hpp"

namespace sculpt::tools::report {

struct ModelError {
  double mean = 0.0;            ///< mean point distance / diagonal
  double max = 0.0;             ///< largest point distance / diagonal
  double max_normal_deg = 0.0;  ///< largest angle between normals (0 without normals)
};

/// `diagonal` is the reference's bounding-box diagonal (the same for every row of a report).
/// Throws std::invalid_argument when the sizes differ.
ModelError model_error(const ExactState& exact, const deform::PointModel& other, double diagonal);

}  // namespace sculpt::tools::report
