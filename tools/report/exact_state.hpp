#pragma once
// The model as the exact computation keeps it: positions and normals in double, never rounded
// to the float PointModel between frames, so that nothing the report measures is hidden in the
// reference itself.

#include <cstddef>
#include <vector>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::tools::report {

struct ExactState {
  std::vector<deform::Vec3> position;
  std::vector<deform::Vec3> normal;  ///< empty when the model has none

  std::size_t size() const { return position.size(); }
  bool has_normals() const { return !normal.empty(); }

  /// A double copy of `model` (exact: every float is a double).
  static ExactState from(const deform::PointModel& model);
  /// Writes the state into `model` (same size and layout), rounding each value to float once:
  /// the start of an approximation's frame.
  void store(deform::PointModel& model) const;
};

}  // namespace sculpt::tools::report
