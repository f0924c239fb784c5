#include "frame_follower.hpp"

#include <algorithm>
#include <iterator>
#include <limits>
#include <utility>

namespace sculpt::view {
namespace {

// The durable log is flushed every output.flush_interval_ms (100 ms by default): a gap waits
// this many patiences for the log to reach past it before it counts as diverged.
constexpr std::int64_t kLogPatiences = 10;
// "Every frame the log has": the last id asked of the log when the frames lost are not known.
constexpr std::int64_t kLastFrame = std::numeric_limits<std::int64_t>::max();

}  // namespace

FrameFollower::FrameFollower(ApplyFrame apply, CatchUpSource catch_up, std::int64_t patience_ns)
    : apply_(std::move(apply)), catch_up_(std::move(catch_up)), patience_ns_(patience_ns) {}

void FrameFollower::collision(const logging::CollisionRecord& event, std::int64_t now_ns) {
  if (event.frame_id >= next_) {
    Frame& frame = pending_[event.frame_id];
    if (frame.events.empty()) {
      frame.size = std::max<std::size_t>(event.frame_size, 1);
      frame.tick = event.tick;
      frame.first_seen_ns = now_ns;
    }
    if (frame.events.size() < frame.size) frame.events.push_back(event);
  }
  decide(now_ns, false);
}

void FrameFollower::tick(std::int64_t tick, int collisions, std::int64_t now_ns) {
  if (tick >= last_tick_) ticks_[tick] = {collisions, now_ns};
  max_tick_ = std::max(max_tick_, tick);
  decide(now_ns, false);
}

void FrameFollower::settle(std::int64_t now_ns) { decide(now_ns, false); }

void FrameFollower::finish() { decide(now_ns_, true); }

void FrameFollower::decide(std::int64_t now_ns, bool final) {
  now_ns_ = std::max(now_ns_, now_ns);
  while (!pending_.empty()) {
    auto it = pending_.begin();
    const std::int64_t id = it->first;
    Frame& frame = it->second;
    if (id < next_) {  // applied from the log meanwhile
      pending_.erase(it);
      continue;
    }
    const std::int64_t waited = now_ns_ - frame.first_seen_ns;
    const bool patient = !final && waited < patience_ns_;
    if (frame.events.size() < frame.size) {
      if (patient) return;
      // Part of the frame was lost: the frame itself is the gap's last.
      if (!fill_gap(id, waited, final)) return;
      continue;
    }
    if (id == next_ || ticks_explain(frame.tick)) {
      const Frame ready = std::move(frame);
      pending_.erase(it);
      apply(ready.events, id);
      continue;
    }
    if (patient) return;  // the ticks that explain the jump may still be on their way
    if (!fill_gap(id - 1, waited, final)) return;
  }
  check_tail(final);
}

void FrameFollower::check_tail(bool final) {
  // Quiet ticks right after the accounted one change nothing: the accounting moves past them,
  // so that what is left to look at stays short however long the station idles.
  if (const auto accounted = ticks_.find(last_tick_);
      last_tick_ < 0 ||
      (accounted != ticks_.end() && accounted->second.collisions <= static_cast<int>(events_at_last_tick_))) {
    std::int64_t quiet = last_tick_;
    for (auto it = ticks_.upper_bound(last_tick_);
         it != ticks_.end() && it->first == quiet + 1 && it->second.collisions == 0; ++it) {
      quiet = it->first;
    }
    if (quiet > last_tick_) forget_ticks_to(quiet);
  }
  // What is left after the accounted tick: ticks that counted collisions no frame brought, and
  // ticks that never arrived (a viewer started after the station never saw its first ones),
  // each a loss once it has had its patience, or at the end.
  const auto ripe = [&](const TickEntry& e) { return final || now_ns_ - e.arrival_ns >= patience_ns_; };
  std::int64_t collided = 0, newest = -1, through = last_tick_, oldest_arrival = now_ns_;
  bool ticks_missing = false;
  for (auto it = ticks_.upper_bound(last_tick_); it != ticks_.end() && ripe(it->second); ++it) {
    if (it->first != through + 1) ticks_missing = true;
    through = it->first;
    oldest_arrival = std::min(oldest_arrival, it->second.arrival_ns);
    if (it->second.collisions > 0) {
      ++collided;
      newest = it->first;
    }
  }
  if (final && through < max_tick_) ticks_missing = true;
  // The accounted tick itself may have counted more collisions than its frames brought.
  if (const auto accounted = ticks_.find(last_tick_);
      accounted != ticks_.end() && accounted->second.collisions > static_cast<int>(events_at_last_tick_) &&
      ripe(accounted->second)) {
    ++collided;
    newest = std::max(newest, last_tick_);
  }
  if (collided == 0 && !ticks_missing) return;
  if (catch_up_) {
    // Whatever the log holds after the last frame applied is the station's history: all of it.
    // It is flushed every 100 ms, so by the time a tick is ripe the log has its frames.
    const CatchUpResult log = catch_up_(next_, kLastFrame);
    apply_log(log.events, kLastFrame);
    log_damage_ += log.damage;
    if (log_damage_ > 0) {
      // What the damage took is not known: at least a frame, whatever the ticks say next.
      ++gaps_;
      diverged_ += static_cast<std::int64_t>(log_damage_);
      log_damage_ = 0;
    }
    if (last_tick_ >= newest) {
      ++gaps_;
      forget_ticks_to(through);
      return;
    }
    if (!final && now_ns_ - oldest_arrival < kLogPatiences * patience_ns_) return;
  }
  ++gaps_;
  // Each collided tick is at least one frame; ticks that never arrived may hide more.
  diverged_ += std::max<std::int64_t>(collided, 1);
  forget_ticks_to(std::max(through, newest));
}

void FrameFollower::forget_ticks_to(std::int64_t tick) {
  // From here the tick accounting starts again: what the copy lacks is counted already.
  if (tick <= last_tick_) return;
  const auto at = ticks_.find(tick);
  last_tick_ = tick;
  events_at_last_tick_ = at == ticks_.end() ? 0 : static_cast<std::size_t>(std::max(at->second.collisions, 0));
  ticks_.erase(ticks_.begin(), ticks_.lower_bound(last_tick_));
}

FrameFollower::LogFrames FrameFollower::apply_log(const std::vector<logging::CollisionRecord>& events,
                                                  std::int64_t last) {
  // The log's events, one complete frame at a time, in order.
  LogFrames frames;
  std::size_t begin = 0;
  while (begin < events.size()) {
    std::size_t end = begin + 1;
    const std::int64_t id = events[begin].frame_id;
    while (end < events.size() && events[end].frame_id == id) ++end;
    if (id >= next_ && id <= last) {
      if (end - begin == std::max<std::size_t>(events[begin].frame_size, 1)) {
        apply(std::span(events).subspan(begin, end - begin), id);
        ++caught_up_;
        ++frames.applied;
      } else {
        ++frames.short_of_events;
      }
    }
    begin = end;
  }
  return frames;
}

bool FrameFollower::ticks_explain(std::int64_t tick) const {
  if (last_tick_ >= 0) {
    const auto at = ticks_.find(last_tick_);
    // The earlier frame's tick counted more collisions than arrived: a frame of that tick is lost.
    if (at == ticks_.end() || at->second.collisions < 0 ||
        static_cast<std::size_t>(at->second.collisions) > events_at_last_tick_)
      return false;
  }
  for (std::int64_t t = last_tick_ + 1; t < tick; ++t) {
    const auto at = ticks_.find(t);
    if (at == ticks_.end() || at->second.collisions != 0) return false;
  }
  return true;
}

bool FrameFollower::fill_gap(std::int64_t last, std::int64_t waited_ns, bool final) {
  if (catch_up_) {
    const CatchUpResult log = catch_up_(next_, last);
    log_damage_ += log.damage;  // an answer that does not reach yet may have found it
    if (log.reached) {
      // The log reaches past the gap, so each of its frames is whole unless damage took some of
      // it. Ids it lacks are frames that moved nothing, except where it showed damage: then
      // every id it could not fill counts (an upper bound, as for a jump). A frame short of
      // events is lost either way.
      const std::int64_t ids = last - next_ + 1;
      const LogFrames frames = apply_log(log.events, last);
      diverged_ += log_damage_ > 0 ? ids - frames.applied : frames.short_of_events;
      log_damage_ = 0;
      ++gaps_;
      next_ = last + 1;
      return true;
    }
    if (!final && waited_ns < kLogPatiences * patience_ns_) return false;
  }
  ++gaps_;
  diverged_ += last - next_ + 1;
  // What the lost frames' ticks counted is unknown from here on: the tick accounting starts
  // again at the lost frame's tick, so that the next jump is judged by the ticks after it.
  if (const auto lost = pending_.find(last); lost != pending_.end()) {
    last_tick_ = lost->second.tick;
    events_at_last_tick_ = lost->second.size;
    ticks_.erase(ticks_.begin(), ticks_.lower_bound(last_tick_));
  }
  next_ = last + 1;
  return true;
}

void FrameFollower::apply(std::span<const logging::CollisionRecord> frame, std::int64_t id) {
  apply_(frame);
  ++applied_;
  next_ = id + 1;
  const std::int64_t tick = frame.front().tick;
  if (tick == last_tick_) {
    events_at_last_tick_ += frame.size();
  } else if (tick > last_tick_) {
    last_tick_ = tick;
    events_at_last_tick_ = frame.size();
  }
  ticks_.erase(ticks_.begin(), ticks_.lower_bound(last_tick_));
}

}  // namespace sculpt::view
