#include "session_log.hpp"

#include "frame_follower.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::view {

SessionLog read_session_log(const std::string& path) {
  SessionLog log;
  const auto take = [&](const logging::LogEvent& event) {
    std::string error;
    if (event.channel == logging::kCollisionChannel) {
      sculpt_lcm::collision_event_t message;
      logging::CollisionRecord record;
      if (logging::decode(event, message, error) && logging::from_lcm(message, record)) {
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

CatchUpResult catch_up_from(const std::string& path, std::int64_t first, std::int64_t last) {
  CatchUpResult result;
  // A log still being written ends in a cut event; that is its unflushed tail, not damage.
  for (const logging::CollisionRecord& r : read_session_log(path).collisions) {
    if (r.frame_id >= first && r.frame_id <= last) result.events.push_back(r);
    if (r.frame_id > last) result.reached = true;
  }
  return result;
}

}  // namespace sculpt::view
