#pragma once
// The cases of issue 7's stability sweep: degenerate single frames over the material, kernel,
// weight-form, precision, G and scale axes, and strokes where each frame's output is the next
// frame's input.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stroke_runner.hpp"
#include "surface_mesh.hpp"
#include "surface_side.hpp"

namespace sculpt::tools::check {

struct CaseSpec {
  std::string name;
  std::string group;  ///< the scenario, without the settings
  bool stroke = false;
  CaseSettings settings;
  std::shared_ptr<const deform::PointModel> model;  ///< in base coordinates
  Outside outside;
  /// The model's surface for the mesh oracle, or null (the PCA plane judges alone).
  std::shared_ptr<const SurfaceMesh> mesh;
  std::function<void(StrokeRunner&)> drive;
  bool invariants = true;  ///< run the G, scale and rigid-motion comparisons
  std::string skipped;     ///< non-empty: the case cannot run here, and why
};

struct SweepOptions {
  bool quick = false;
  std::string scan_path;  ///< the bust (or any scan) for the long push series
};

/// Every case of the sweep, in table order. Reads the scan; a missing scan gives a skipped case.
std::vector<CaseSpec> make_cases(const SweepOptions& options);

}  // namespace sculpt::tools::check
