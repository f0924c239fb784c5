// The follower's rules, on hand-made event streams: frames applied strictly in id order, a jump
// in the ids accepted only when the tick statistics show the frames between moved nothing, and
// every other loss either filled from the log or counted as diverged.
#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <vector>

#include "frame_follower.hpp"
#include "support/nanoseconds.hpp"

namespace sculpt::view {
namespace {

using test::kMs;

logging::CollisionRecord event(std::int64_t frame_id, std::int64_t tick, int frame_size = 1, int finger = 1) {
  logging::CollisionRecord r;
  r.frame_id = frame_id;
  r.tick = tick;
  r.frame_size = static_cast<std::uint8_t>(frame_size);
  r.finger = static_cast<std::uint8_t>(finger);
  return r;
}

// The ids of the frames applied, in order, and their sizes.
struct Applied {
  std::vector<std::int64_t> ids;
  std::vector<std::size_t> sizes;
  FrameFollower::ApplyFrame sink() {
    return [this](std::span<const logging::CollisionRecord> f) {
      ids.push_back(f.front().frame_id);
      sizes.push_back(f.size());
    };
  }
};

// What a log of `events` answers for frame ids [first, last] (not whether it reaches past).
CatchUpResult from_log(std::initializer_list<logging::CollisionRecord> events, std::int64_t first, std::int64_t last) {
  CatchUpResult r;
  for (const auto& e : events) {
    if (e.frame_id >= first && e.frame_id <= last) r.events.push_back(e);
  }
  return r;
}

// Frame 0 arrives live at tick 0, then ticks 1.. with `collisions` each, and the frame
// `last_frame` (one event) with the last of them: the frames between were lost.
void lost_between(FrameFollower& f, std::initializer_list<int> collisions, std::int64_t last_frame) {
  f.tick(0, 1, 0);
  f.collision(event(0, 0), 0);
  std::int64_t tick = 0;
  for (const int c : collisions) f.tick(++tick, c, 0);
  f.collision(event(last_frame, tick), 0);
}

// Ticks [first, last] with no collision.
void quiet_ticks(FrameFollower& f, std::int64_t first, std::int64_t last, std::int64_t now) {
  for (std::int64_t t = first; t <= last; ++t) f.tick(t, 0, now);
}

TEST(FrameFollower, ConsecutiveFramesAreAppliedInIdOrderWhateverTheirArrivalOrder) {
  Applied applied;
  FrameFollower f(applied.sink());
  f.tick(0, 1, 0);
  f.collision(event(0, 0), 0);
  f.collision(event(2, 2), 1);  // overtook frame 1
  f.collision(event(1, 1), 2);
  f.tick(1, 1, 3);
  f.tick(2, 1, 3);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(f.frame_id(), 2);
  EXPECT_FALSE(f.diverged());
  EXPECT_EQ(f.gaps(), 0u);
}

TEST(FrameFollower, AFrameWaitsForAllItsEvents) {
  Applied applied;
  FrameFollower f(applied.sink());
  f.collision(event(0, 0, 2, 1), 0);
  EXPECT_TRUE(applied.ids.empty());
  f.collision(event(0, 0, 2, 2), 1);
  ASSERT_EQ(applied.ids.size(), 1u);
  EXPECT_EQ(applied.sizes[0], 2u);
}

TEST(FrameFollower, AJumpOverQuietTicksIsNoGap) {
  Applied applied;
  FrameFollower f(applied.sink());
  // Frames 0..4 ran without contact (ticks 0..4 count no collision), frame 5 pressed at tick 5.
  quiet_ticks(f, 0, 4, 0);
  f.collision(event(5, 5), 1);
  f.tick(5, 1, 1);
  // Frames 6..9 again without contact, then frame 10.
  quiet_ticks(f, 6, 9, 2);
  f.collision(event(10, 10), 3);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{5, 10}));
  EXPECT_FALSE(f.diverged());
  EXPECT_EQ(f.gaps(), 0u);
}

TEST(FrameFollower, AJumpWaitsForTheTicksThatExplainIt) {
  Applied applied;
  FrameFollower f(applied.sink());
  f.collision(event(3, 3), 0);  // its ticks are still on their way
  EXPECT_TRUE(applied.ids.empty());
  quiet_ticks(f, 0, 2, 10 * kMs);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{3}));
  EXPECT_FALSE(f.diverged());
}

TEST(FrameFollower, ALostFrameBetweenTwoIsCountedAsDivergedAfterThePatience) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  f.tick(0, 1, 0);
  f.collision(event(0, 0), 0);
  f.tick(1, 1, 0);  // frame 1 at tick 1: its event was lost
  f.tick(2, 1, 0);
  f.collision(event(2, 2), 0);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0}));  // waits: the tick says tick 1 collided
  f.settle(50 * kMs);
  EXPECT_FALSE(f.diverged());
  f.settle(150 * kMs);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0, 2}));
  EXPECT_TRUE(f.diverged());
  EXPECT_EQ(f.diverged_frames(), 1);
  EXPECT_EQ(f.gaps(), 1u);
}

TEST(FrameFollower, AJumpWithAMissingTickIsAGapEvenWhenNothingWasLost) {
  // The follower cannot tell "no collision" from "lost" without the tick: it says diverged
  // rather than show a model that might be wrong.
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  f.tick(0, 0, 0);
  f.tick(2, 0, 0);  // tick 1 lost
  f.collision(event(3, 3), 0);
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{3}));
  EXPECT_EQ(f.diverged_frames(), 3);  // frames 0..2 unaccounted
}

TEST(FrameFollower, AFrameMissingSomeOfItsEventsIsLost) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  f.collision(event(0, 0, 2, 1), 0);  // its second event never comes
  f.collision(event(1, 1), 0);
  f.tick(0, 2, 0);
  f.tick(1, 1, 0);
  f.settle(200 * kMs);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(f.diverged_frames(), 1);
}

TEST(FrameFollower, ALateStartIsAGapSinceTheFirstFramesWereNeverSeen) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  quiet_ticks(f, 500, 519, 0);  // the viewer started at tick 500
  f.collision(event(520, 520), 0);
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{520}));
  EXPECT_EQ(f.diverged_frames(), 520);
}

TEST(FrameFollower, AGapIsFilledFromTheLogOnceTheLogReachesPastIt) {
  Applied applied;
  std::vector<logging::CollisionRecord> log = {event(0, 0), event(1, 1, 2, 1), event(1, 1, 2, 2), event(2, 2)};
  std::size_t flushed = 2;  // the log's tail is not yet on disk
  std::vector<std::pair<std::int64_t, std::int64_t>> asked;
  const auto source = [&](std::int64_t first, std::int64_t last) {
    asked.emplace_back(first, last);
    CatchUpResult r;
    for (std::size_t i = 0; i < flushed; ++i) {
      if (log[i].frame_id >= first && log[i].frame_id <= last) r.events.push_back(log[i]);
      if (log[i].frame_id > last) r.reached = true;
    }
    return r;
  };
  FrameFollower f(applied.sink(), source, 100 * kMs);
  f.tick(0, 1, 0);
  f.collision(log[0], 0);
  f.tick(1, 2, 0);
  f.tick(2, 1, 0);
  f.collision(log[3], 0);  // frame 1's two events were lost
  f.settle(200 * kMs);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0}));  // the log does not reach frame 2 yet
  flushed = 4;
  f.settle(300 * kMs);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0, 1, 2}));
  EXPECT_EQ(applied.sizes[1], 2u);
  EXPECT_FALSE(f.diverged());
  EXPECT_EQ(f.frames_caught_up(), 1u);
  EXPECT_EQ(f.gaps(), 1u);
  ASSERT_FALSE(asked.empty());
  EXPECT_EQ(asked.back(), (std::pair<std::int64_t, std::int64_t>{1, 1}));
}

// The log answers a gap of frames 1-3: frame 2 whole, frame 3 short of one of its two events,
// frame 1 absent. With no damage seen, an absent id is a frame that moved nothing; the short
// frame is lost. With damage (a collision that did not match its check, say), every id the log
// could not fill counts.
TEST(FrameFollower, ALogGapWithDamageCountsEveryFrameItCouldNotFill) {
  for (const std::size_t damage : {std::size_t{0}, std::size_t{1}}) {
    Applied applied;
    const auto source = [&](std::int64_t first, std::int64_t last) {
      CatchUpResult r = from_log({event(2, 2), event(3, 3, 2, 1), event(4, 4)}, first, last);
      r.reached = last < 4;
      r.damage = damage;
      return r;
    };
    FrameFollower f(applied.sink(), source, 10 * kMs);
    lost_between(f, {0, 1, 2, 1}, 4);  // frames 1-3 never arrived live
    f.settle(100 * kMs);
    f.finish();
    EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0, 2, 4})) << "damage " << damage;
    EXPECT_EQ(f.diverged_frames(), damage > 0 ? 2 : 1) << "damage " << damage;
    EXPECT_TRUE(f.diverged());
  }
}

// Damage the log showed in an answer that did not reach past the gap yet still counts when a
// later answer fills the gap: the catch-up reports each damage once.
TEST(FrameFollower, DamageSeenBeforeTheLogReachesPastTheGapStillCounts) {
  Applied applied;
  int answers = 0;
  const auto source = [&](std::int64_t first, std::int64_t last) {
    ++answers;
    if (answers == 1) {
      CatchUpResult r;
      r.damage = 1;  // the log so far: frame 1's event did not match its check
      return r;
    }
    CatchUpResult r = from_log({event(2, 2)}, first, last);
    r.reached = true;  // frame 3 is in the log now
    return r;
  };
  FrameFollower f(applied.sink(), source, 10 * kMs);
  lost_between(f, {1, 1, 1}, 3);  // frames 1 and 2 never arrived live
  f.settle(20 * kMs);             // the first answer: damage, not reached
  f.settle(40 * kMs);             // the second: reached, no new damage
  f.finish();
  EXPECT_GE(answers, 2);
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{0, 2, 3}));
  EXPECT_EQ(f.diverged_frames(), 1) << "frame 1, which the damage took";
}

TEST(FrameFollower, ALogThatNeverReachesPastTheGapLeavesItDiverged) {
  Applied applied;
  const auto source = [](std::int64_t, std::int64_t) { return CatchUpResult{}; };
  FrameFollower f(applied.sink(), source, 10 * kMs);
  f.tick(0, 1, 0);
  f.tick(1, 1, 0);
  f.collision(event(1, 1), 0);
  f.settle(50 * kMs);
  EXPECT_TRUE(applied.ids.empty());  // still waiting for the log
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(f.diverged_frames(), 1);
}

TEST(FrameFollower, ATickThatCollidedWithoutAFrameIsALossEvenWithNothingAfterIt) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  quiet_ticks(f, 0, 9, 0);
  f.tick(10, 1, 0);  // its frame never arrives, and no later frame shows a jump
  quiet_ticks(f, 11, 20, 0);
  f.settle(50 * kMs);
  EXPECT_FALSE(f.diverged());
  f.settle(150 * kMs);
  EXPECT_EQ(f.diverged_frames(), 1);
  EXPECT_TRUE(applied.ids.empty());
}

TEST(FrameFollower, QuietTicksAreNoLossHoweverMany) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  quiet_ticks(f, 0, 99'999, 0);
  f.collision(event(7, 100'000), 1);
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{7}));
  EXPECT_FALSE(f.diverged());
}

TEST(FrameFollower, AViewerStartedLateThatSawNoFrameStillKnowsItMayHaveMissedSome) {
  Applied applied;
  FrameFollower f(applied.sink(), {}, 100 * kMs);
  quiet_ticks(f, 3000, 3500, 0);  // ticks 0..2999 were before it started
  f.settle(50 * kMs);
  EXPECT_FALSE(f.diverged());  // the first ticks it has may yet be followed by the missing ones
  f.finish();
  EXPECT_TRUE(f.diverged());
}

TEST(FrameFollower, AViewerStartedLateCatchesUpTheWholeLog) {
  Applied applied;
  const std::vector<logging::CollisionRecord> log = {event(4, 1000), event(5, 1001)};
  const auto source = [&](std::int64_t first, std::int64_t) {
    CatchUpResult r;
    for (const auto& e : log) {
      if (e.frame_id >= first) r.events.push_back(e);
    }
    return r;
  };
  FrameFollower f(applied.sink(), source, 100 * kMs);
  quiet_ticks(f, 3000, 3500, 0);
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{4, 5}));
  EXPECT_FALSE(f.diverged());
  EXPECT_EQ(f.frames_caught_up(), 2u);
}

// The same late viewer, with the log showing damage on the way (a collision that did not match
// its check): what it could take is applied, and the copy is not vouched for.
TEST(FrameFollower, AViewerStartedLateOverADamagedLogSaysItDiverged) {
  Applied applied;
  const auto source = [&](std::int64_t first, std::int64_t) {
    CatchUpResult r;
    for (const auto& e : {event(4, 1000), event(5, 1001)}) {
      if (e.frame_id >= first) r.events.push_back(e);
    }
    r.damage = first == 0 ? 1 : 0;  // found by the first read only
    return r;
  };
  FrameFollower f(applied.sink(), source, 100 * kMs);
  quiet_ticks(f, 3000, 3500, 0);
  f.finish();
  EXPECT_EQ(applied.ids, (std::vector<std::int64_t>{4, 5}));
  EXPECT_TRUE(f.diverged());
  EXPECT_EQ(f.diverged_frames(), 1);
}

}  // namespace
}  // namespace sculpt::view
