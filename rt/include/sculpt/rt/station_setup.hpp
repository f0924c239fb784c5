#pragma once
// From a scene to a ready station: the model loaded with the normals it asks for, defaults
// derived from the model's own scale, registration calibrated, backends built.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sculpt/deform/model_identity.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/normal_check.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/similarity_transform.hpp"
#include "sculpt/rt/station.hpp"

namespace sculpt::rt {

struct StationSetup {
  deform::PointModel model;
  StationSettings settings;
  /// "file", "from faces", "estimated (PCA)", "none"; "file (<describe(normal_report)>)" when
  /// check_normals repaired some of the file's normals.
  std::string normals_source;
  deform::NormalReport normal_report;      ///< what check_normals did to the file's normals
  deform::TypicalSpacing spacing;          ///< the model's length scale, and which statistic gave it
  std::optional<Calibration> calibration;  ///< when the scene gave landmarks
  std::vector<std::string> notes;          ///< defaults derived, for the user to see once
  /// A reduced-set session (heuristic.reduced_ratio < 1): the full model's identity, taken
  /// before the reduction, so the session header can name the model the log transfers to.
  std::optional<deform::ModelIdentity> full_model;
};

/// Loads and prepares everything the scene names (set-up: may allocate and throw; model file
/// errors are deform::ModelFileError, setting errors std::invalid_argument naming the key).
StationSetup prepare_station(const Scene& scene);

/// The station for a prepared set-up: builds the scene's glove source and haptic sink (and
/// nothing else). `setup` must outlive the station.
std::unique_ptr<Station> make_station(StationSetup& setup, const Scene& scene);

}  // namespace sculpt::rt
