#include "sculpt/rt/session_header.hpp"

#include "sculpt/base/version.hpp"

namespace sculpt::rt {

SessionHeader session_header(const Scene& scene, const StationSetup& setup) {
  SessionHeader h;
  h.version = base::project_version();
  h.scene_path = scene.file;
  h.scene_text = scene.text;
  h.model = deform::model_identity(setup.model);
  if (setup.full_model) {
    h.full = setup.full_model;
    h.reduced_ratio = scene.heuristic.reduced_ratio;
  }
  return h;
}

ModelMatch match_model(const SessionHeader& header, const deform::ModelIdentity& model) noexcept {
  if (model == header.model) return ModelMatch::kRecording;
  if (header.full && model == *header.full) return ModelMatch::kFull;
  return ModelMatch::kOther;
}

}  // namespace sculpt::rt
