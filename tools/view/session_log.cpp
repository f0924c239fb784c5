#include "session_log.hpp"

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::view {

bool collision_from(const logging::LogEvent& event, logging::CollisionRecord& out) {
  sculpt_lcm::collision_event_t message;
  std::string error;
  return logging::decode(event, message, error) && logging::from_lcm(message, out);
}

SessionLog read_session_log(const std::string& path) {
  SessionLog log;
  const auto take = [&](const logging::LogEvent& event) {
    std::string error;
    if (event.channel == logging::kCollisionChannel) {
      logging::CollisionRecord record;
      if (collision_from(event, record)) {
        log.collisions.push_back(record);
      } else {
        ++log.damaged;
      }
    } else if (event.channel == logging::kFingertipChannel) {
      sculpt_lcm::fingertip_state_t tip;
      if (!logging::decode(event, tip, error)) {
        ++log.damaged;
        return;
      }
      log.fingertips.push_back({tip.tick,
                                tip.hand,
                                tip.finger,
                                {tip.registered[0], tip.registered[1], tip.registered[2]},
                                tip.in_contact != 0});
    } else if (event.channel == logging::kTickChannel) {
      sculpt_lcm::tick_stats_t tick;
      if (!logging::decode(event, tick, error)) {
        ++log.damaged;
        return;
      }
      log.ticks.push_back({tick.tick, tick.collisions, tick.tick_time_us, tick.budget_us, tick.overruns});
    }
  };
  logging::for_each_event(path, take, [&](std::uint64_t, const std::string&) { ++log.damaged; });
  return log;
}

}  // namespace sculpt::view
