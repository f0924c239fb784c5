#include "sculpt/rt/session_recorder.hpp"

#include <stdexcept>

#if SCULPT_HAS_LCM
#include "lcm_session_recorder.hpp"
#endif

namespace sculpt::rt {

std::unique_ptr<SessionRecorder> make_session_recorder(const Scene& scene, const std::optional<SessionHeader>& header) {
  if (!scene.output.log && !scene.lcm.publish) return nullptr;
#if SCULPT_HAS_LCM
  return std::make_unique<LcmSessionRecorder>(scene, header);
#else
  (void)header;
  throw std::runtime_error(
      "the scene asks for an event log or live publishing, which need LCM; "
      "reconfigure with -DSCULPT_WITH_LCM=ON");
#endif
}

}  // namespace sculpt::rt
