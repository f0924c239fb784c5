#pragma once
// The durable log is the edit history: a recording that lost events (the logger's queue full,
// or writes that failed: a full disk, a file size limit, a device gone) no longer gives the
// model from the base, and must not pass as a clean run.

#include <string>

#include "sculpt/rt/session_recorder.hpp"

namespace sculpt::tools {

/// True when the recording wrote no log or every event to it. Otherwise says so on stderr in
/// one line, naming the log, what it lost and `model` (what the base and the log no longer
/// give), and returns false: the caller exits kExitDamage.
bool log_is_complete(const rt::RecordingCounts& counts, const std::string& model);

}  // namespace sculpt::tools
