#pragma once
// A session recorded by `sculpt run` (its durable log): the scene it ran, from the log's own
// header, and the glove samples it received, so that the report re-runs what the user did.

#include <string>
#include <vector>

#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/rt/replay_glove_source.hpp"
#include "sculpt/rt/scene.hpp"

namespace sculpt::tools::report {

struct LoggedSession {
  rt::Scene scene;        ///< parsed from the header's scene text
  rt::SampleLog samples;  ///< stamped with the log's time base, and which live tick took each
};

/// Reads the log at `path`. Relative paths in the scene resolve against the directory of the
/// scene as the header names it. Throws std::invalid_argument for a log without a session
/// header or without glove samples, for a build without LCM, and whatever the log reader and
/// the scene parser throw; damaged events are passed over (sculpt replay reports them).
LoggedSession read_logged_session(const std::string& path);

}  // namespace sculpt::tools::report
