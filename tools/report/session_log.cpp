#include "session_log.hpp"

#include <filesystem>
#include <stdexcept>

#if SCULPT_HAS_LCM
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt/logging/taken_ticks.hpp"
#include "sculpt/rt/lcm_session_header.hpp"
#endif

namespace sculpt::tools::report {

LoggedSession read_logged_session(const std::string& path) {
#if SCULPT_HAS_LCM
  LoggedSession out;
  std::optional<rt::SessionHeader> header;
  logging::TakenTicks taken;
  logging::for_each_event(
      path,
      [&](const logging::LogEvent& event) {
        std::string error;
        taken.event(event.channel);
        if (event.channel == logging::kSessionChannel && !header) {
          sculpt_lcm::session_header_t message;
          rt::SessionHeader h;
          if (logging::decode(event, message, error) && rt::from_lcm(message, h, error)) header = std::move(h);
        } else if (event.channel == logging::kGloveChannel) {
          sculpt_lcm::glove_sample_t message;
          hal::GloveSample sample;
          // The log's time base, as sculpt replay reads it.
          if (!logging::decode(event, message, error) || !hal::from_lcm(message, sample) ||
              !logging::log_time_ns(message.utime, sample.receive_time_ns)) {
            taken.damage();
            return;
          }
          out.samples.samples.push_back(sample);
          taken.sample();
        }
      },
      [&](std::uint64_t, const std::string&) { taken.damage(); });
  if (!header) throw std::invalid_argument(path + ": no session header (is it a log written by sculpt run?)");
  if (out.samples.samples.empty()) throw std::invalid_argument(path + ": no glove samples to re-run");
  out.samples.taken = taken.finish();
  const std::filesystem::path scene_path(header->scene_path);
  out.scene = rt::parse_scene(header->scene_text, header->scene_path, scene_path.parent_path().string());
  return out;
#else
  throw std::invalid_argument(path + ": reading a session log needs a build with LCM (SCULPT_WITH_LCM)");
#endif
}

}  // namespace sculpt::tools::report
