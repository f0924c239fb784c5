#pragma once
// What a session log says about itself before its first event: the program's version, the
// scene and its settings, and the model it ran on (with a reduced model set, also the full
// model it was drawn from). Plain data, so rt builds without LCM; lcm_session_header.hpp puts
// it on the wire.

#include <cstdint>
#include <optional>
#include <string>

#include "sculpt/deform/model_identity.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station_setup.hpp"

namespace sculpt::rt {

/// The header schema this build writes and reads (sculpt_lcm::session_header_t::SCHEMA).
inline constexpr std::int32_t kSessionSchema = 1;

struct SessionHeader {
  std::int32_t schema = kSessionSchema;
  std::string version;                        ///< the writer's project version
  std::string scene_path;                     ///< as given
  std::string scene_text;                     ///< the scene's TOML text
  deform::ModelIdentity model;                ///< what the station sculpted
  std::optional<deform::ModelIdentity> full;  ///< a reduced-set session: the full model
  double reduced_ratio = 1.0;
};

/// The header of a session about to run on `setup` (set-up time: before the loop starts, so
/// the model is still the one loaded).
SessionHeader session_header(const Scene& scene, const StationSetup& setup);

/// How a model given to replay relates to the session.
enum class ModelMatch {
  kRecording,  ///< the model the session sculpted
  kFull,       ///< the full model a reduced-set session was drawn from (the thesis's transfer)
  kOther,      ///< neither
};

ModelMatch match_model(const SessionHeader& header, const deform::ModelIdentity& model) noexcept;

}  // namespace sculpt::rt
