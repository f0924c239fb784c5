#pragma once
// The LCM implementation of the station's recorder: every sample, fingertip, collision, haptic
// command and tick goes to the durable log (when the scene names one) and to the live channels
// (when it asks to publish). Built only with LCM.

#include <memory>

#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station_recorder.hpp"

namespace sculpt::tools {

class Recording {
 public:
  virtual ~Recording() = default;
  virtual rt::StationRecorder* recorder() = 0;
  virtual void start() = 0;
  /// Drains, flushes and closes; idempotent.
  virtual void stop() = 0;
  virtual void flush() = 0;
  /// Counts for the run's summary (JSON text).
  virtual std::string summary_json() const = 0;
  /// Collision events recorded so far.
  virtual std::uint64_t collisions_logged() const = 0;
};

/// nullptr when the scene names neither a log nor live publishing; throws with a clear message
/// when it does and this build has no LCM.
std::unique_ptr<Recording> make_recording(const rt::Scene& scene);

}  // namespace sculpt::tools
