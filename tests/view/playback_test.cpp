// The playback keys: pause, step, speed, and frames due at their recorded time over the speed.
#include <gtest/gtest.h>

#include "playback.hpp"

namespace sculpt::view {
namespace {

TEST(Playback, FramesAreDueAtTheirRecordedTime) {
  Playback p({0.5, 1.0, 1.5}, false);
  EXPECT_EQ(p.status(), "frame 0/3 playing speed 1x");
  p.advance(0.6);
  EXPECT_EQ(p.due(), 1u);
  p.advance(1.0);
  EXPECT_EQ(p.due(), 3u);
  EXPECT_TRUE(p.ended());
  EXPECT_EQ(p.status(), "frame 3/3 ended speed 1x");
}

TEST(Playback, StepMovesOneFrameOnlyWhilePaused) {
  Playback p({5.0, 6.0, 7.0}, true);
  p.advance(100.0);
  EXPECT_EQ(p.due(), 0u);
  EXPECT_TRUE(p.key(Key::kStep));
  EXPECT_EQ(p.due(), 1u);
  EXPECT_TRUE(p.key(Key::kStep));
  EXPECT_EQ(p.status(), "frame 2/3 paused speed 1x");
  EXPECT_TRUE(p.key(Key::kPause));
  EXPECT_FALSE(p.key(Key::kStep));
  EXPECT_EQ(p.due(), 2u);
  // Resumed at frame 2's time, the next frame is a second of recorded time away.
  p.advance(0.5);
  EXPECT_EQ(p.due(), 2u);
  p.advance(0.6);
  EXPECT_EQ(p.due(), 3u);
}

TEST(Playback, SpeedDoublesAndHalves) {
  Playback p({1.0, 2.0}, false);
  EXPECT_TRUE(p.key(Key::kFaster));
  EXPECT_EQ(p.speed(), 2.0);
  p.advance(0.55);  // 1.1 s of recorded time
  EXPECT_EQ(p.due(), 1u);
  EXPECT_TRUE(p.key(Key::kSlower));
  EXPECT_TRUE(p.key(Key::kSlower));
  EXPECT_EQ(p.status(), "frame 1/2 playing speed 0.5x");
}

}  // namespace
}  // namespace sculpt::view
