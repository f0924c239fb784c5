#pragma once
// The viewer's copy of the edit history as it arrives over UDP, which drops bursts. Frames are
// re-applied strictly in frame-id order, and only when nothing before them can have been lost.
//
// Frame ids (rt::Station) grow by one per deformation frame, but a frame that moved nothing
// takes an id and publishes no event, so a jump in the ids alone does not prove a loss. The
// tick statistics decide it: every tick publishes one SCULPT_TICK with consecutive tick numbers
// and its collision count, so a jump is clean when every tick between the two frames arrived
// and reported no collision, and the earlier frame's tick reported no more events than arrived.
// Anything else is a gap: filled from the durable log when there is one (catch-up), otherwise
// counted as diverged, because a wrong model must never be shown as if it were right. The same
// accounting runs with no frame waiting: a tick that counted collisions no frame brought, or
// (at the end) ticks that never arrived, such as a late-started viewer's first ones.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <vector>

#include "sculpt/logging/records.hpp"

namespace sculpt::view {

/// What the durable log holds for frame ids [first, last].
struct CatchUpResult {
  std::vector<logging::CollisionRecord> events;  ///< in log order
  /// The log already reaches past `last` (it holds a later frame), so every frame up to `last`
  /// is in it: a log is written in order and only its unflushed tail can be missing.
  bool reached = false;
  /// Damage the log showed since the last answer (a collision that did not match its check,
  /// say): the frames it could have held cannot be vouched for.
  std::size_t damage = 0;
};

class FrameFollower {
 public:
  /// Applies one complete frame (events sharing one frame_id) to the copy.
  using ApplyFrame = std::function<void(std::span<const logging::CollisionRecord>)>;
  /// Reads the durable log for frame ids [first, last].
  using CatchUpSource = std::function<CatchUpResult(std::int64_t first, std::int64_t last)>;

  /// `patience_ns`: how long a frame waits for the rest of its events, for the ticks that
  /// explain a jump, or for the log to be flushed past a gap, before the gap is final.
  explicit FrameFollower(ApplyFrame apply, CatchUpSource catch_up = {}, std::int64_t patience_ns = 300'000'000);

  /// One SCULPT_COLLISION event, received at `now_ns` (any monotonic clock).
  void collision(const logging::CollisionRecord& event, std::int64_t now_ns);
  /// One SCULPT_TICK: `tick` and the collisions it counted.
  void tick(std::int64_t tick, int collisions, std::int64_t now_ns);
  /// Applies every frame that can be decided at `now_ns`.
  void settle(std::int64_t now_ns);
  /// No more input: decides every waiting frame, gaps included.
  void finish();

  /// The last frame id applied or given up on (-1 before the first).
  std::int64_t frame_id() const { return next_ - 1; }
  std::size_t frames_applied() const { return applied_; }
  std::size_t frames_caught_up() const { return caught_up_; }
  /// Frame ids never applied because their events were lost and no log had them: the copy
  /// differs from the station's by up to this many frames.
  std::int64_t diverged_frames() const { return diverged_; }
  bool diverged() const { return diverged_ > 0; }
  std::size_t gaps() const { return gaps_; }
  /// Frames received and not yet applied.
  std::size_t waiting() const { return pending_.size(); }

 private:
  struct Frame {
    std::vector<logging::CollisionRecord> events;
    std::size_t size = 1;  // frame_size
    std::int64_t tick = 0;
    std::int64_t first_seen_ns = 0;
  };

  struct TickEntry {
    int collisions = 0;
    std::int64_t arrival_ns = 0;
  };

  void decide(std::int64_t now_ns, bool final);
  // Nothing waits: collisions the ticks counted and no frame brought are a loss too.
  void check_tail(bool final);
  void forget_ticks_to(std::int64_t tick);
  // The log's frames in [next_, last]: those applied (complete), and those short of events.
  struct LogFrames {
    std::int64_t applied = 0, short_of_events = 0;
  };
  LogFrames apply_log(const std::vector<logging::CollisionRecord>& events, std::int64_t last);
  bool ticks_explain(std::int64_t tick) const;
  // Frames [next_, last] are not here: from the log, or diverged. False to wait for the log.
  bool fill_gap(std::int64_t last, std::int64_t waited_ns, bool final);
  void apply(std::span<const logging::CollisionRecord> frame, std::int64_t id);

  ApplyFrame apply_;
  CatchUpSource catch_up_;
  std::int64_t patience_ns_;
  std::map<std::int64_t, Frame> pending_;    // by frame id
  std::map<std::int64_t, TickEntry> ticks_;  // from the last applied frame's tick on
  std::int64_t max_tick_ = -1;
  std::int64_t next_ = 0;                // the next frame id to apply
  std::int64_t last_tick_ = -1;          // tick of the last applied frame (-1: none yet)
  std::size_t events_at_last_tick_ = 0;  // events applied with that tick
  std::size_t applied_ = 0;
  std::size_t caught_up_ = 0;
  std::size_t gaps_ = 0;
  std::int64_t diverged_ = 0;
  std::int64_t now_ns_ = 0;
  std::size_t log_damage_ = 0;  // damage the log showed that no gap has counted yet
};

}  // namespace sculpt::view
