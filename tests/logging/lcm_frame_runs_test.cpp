// What a whole frame is, shared by replay, undo and the viewer: hand-built logs whose frames are
// known by construction.
#include "sculpt/logging/frame_runs.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace sculpt::logging {
namespace {

CollisionRecord event(std::int64_t frame_id, std::uint8_t frame_size) {
  CollisionRecord r;
  r.frame_id = frame_id;
  r.frame_size = frame_size;
  return r;
}

TEST(FrameRuns, ARunIsTheConsecutiveEventsOfOneFrameId) {
  // Frame 7 appears twice, apart: two runs, as a log written in order never has.
  const std::vector<CollisionRecord> log{event(3, 1), event(7, 2), event(7, 2), event(8, 1), event(7, 1)};
  std::vector<std::size_t> ends;
  for (std::size_t begin = 0; begin < log.size(); begin = frame_run_end(log, begin))
    ends.push_back(frame_run_end(log, begin));
  EXPECT_EQ(ends, (std::vector<std::size_t>{1, 3, 4, 5}));
}

TEST(FrameRuns, AFrameIsWholeOnlyWhenEveryEventCountsItsEvents) {
  const std::vector<CollisionRecord> whole{event(5, 3), event(5, 3), event(5, 3)};
  EXPECT_TRUE(whole_frame(whole));
  // One event lost: the two left still say three.
  EXPECT_FALSE(whole_frame(std::span(whole).first(2)));
  // Damage that changed one event's count: the first agrees with the run, a later one does not.
  const std::vector<CollisionRecord> disagreeing{event(5, 2), event(5, 3)};
  EXPECT_FALSE(whole_frame(disagreeing));
  // More events than the frame says (a frame id repeated by damage).
  const std::vector<CollisionRecord> extra{event(5, 1), event(5, 1)};
  EXPECT_FALSE(whole_frame(extra));
}

}  // namespace
}  // namespace sculpt::logging
