// TakenTicks: which live tick took each glove sample of a station's log, from the log's order.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/taken_ticks.hpp"

namespace sculpt::logging {
namespace {

TEST(TakenTicks, ALiveTicksEventsEndItsRunOfSamples) {
  TakenTicks taken;
  taken.event(kSessionChannel);  // before every tick: ends nothing
  taken.sample();
  taken.sample();
  taken.event(kFingertipChannel);  // the tick that took both
  taken.event(kFingertipChannel);
  taken.event(kCollisionChannel);
  taken.sample();
  taken.event("SOME_OTHER_CHANNEL");  // logged by no tick of ours
  taken.sample();
  taken.event(kTickChannel);
  taken.sample();
  taken.event(kHapticChannel);
  taken.sample();
  taken.damage();  // whatever was lost, these two samples are not joined
  taken.sample();
  taken.event(kFingertipChannel);
  taken.sample();  // a crash's tail: no event of its tick followed
  taken.sample();
  EXPECT_EQ(taken.finish(), (std::vector<std::int64_t>{0, 0, 1, 1, 2, 3, 4, -1, -1}));
}

}  // namespace
}  // namespace sculpt::logging
