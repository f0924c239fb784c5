#include "frame_follower.hpp"

#include <algorithm>
#include <utility>

namespace sculpt::view {
namespace {

// The durable log is flushed every output.flush_interval_ms (100 ms by default): a gap waits
// this many patiences for the log to reach past it before it counts as diverged.
constexpr std::int64_t kLogPatiences = 10;

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
  if (tick >= last_tick_) ticks_[tick] = collisions;
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
}

bool FrameFollower::ticks_explain(std::int64_t tick) const {
  if (last_tick_ >= 0) {
    const auto at = ticks_.find(last_tick_);
    // The earlier frame's tick counted more collisions than arrived: a frame of that tick is lost.
    if (at == ticks_.end() || at->second < 0 || static_cast<std::size_t>(at->second) > events_at_last_tick_)
      return false;
  }
  for (std::int64_t t = last_tick_ + 1; t < tick; ++t) {
    const auto at = ticks_.find(t);
    if (at == ticks_.end() || at->second != 0) return false;
  }
  return true;
}

bool FrameFollower::fill_gap(std::int64_t last, std::int64_t waited_ns, bool final) {
  if (catch_up_) {
    const CatchUpResult log = catch_up_(next_, last);
    if (log.reached) {
      // The log's events for these ids, one frame at a time, in order.
      std::size_t begin = 0;
      while (begin < log.events.size()) {
        std::size_t end = begin + 1;
        const std::int64_t id = log.events[begin].frame_id;
        while (end < log.events.size() && log.events[end].frame_id == id) ++end;
        if (id >= next_ && id <= last) {
          apply(std::span(log.events).subspan(begin, end - begin), id);
          ++caught_up_;
        }
        begin = end;
      }
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
  } else {
    last_tick_ = tick;
    events_at_last_tick_ = frame.size();
  }
  ticks_.erase(ticks_.begin(), ticks_.lower_bound(last_tick_));
}

}  // namespace sculpt::view
