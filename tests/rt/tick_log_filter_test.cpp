// Which ticks the durable log keeps: each kind of event keeps its tick, a quiet run keeps one
// tick per interval, and every tick is either kept or counted as left out.
#include "sculpt/rt/tick_log_filter.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace sculpt::rt {
namespace {

constexpr double kSlowUs = 500.0;  // half of a 1 kHz period

// A quiet tick: a live glove, nothing pressed, fast.
TickReport quiet(std::uint64_t tick) {
  TickReport r;
  r.tick = tick;
  r.glove = GloveState::kLive;
  return r;
}

TEST(TickLogFilter, AQuietRunKeepsOneTickPerIntervalAndCountsTheRest) {
  TickLogFilter filter(100, kSlowUs);
  std::vector<std::uint64_t> kept;
  for (std::uint64_t t = 0; t < 1000; ++t) {
    if (filter.keep(quiet(t), 0, 0, 10.0)) kept.push_back(t);
  }
  // The first tick (the glove's state is news), then every 100th after it.
  const std::vector<std::uint64_t> expected = {0, 100, 200, 300, 400, 500, 600, 700, 800, 900};
  EXPECT_EQ(kept, expected);
  EXPECT_EQ(filter.kept(), 10u);
  EXPECT_EQ(filter.left_out(), 990u);
}

TEST(TickLogFilter, IntervalZeroOrOneKeepsEveryTick) {
  for (const std::uint64_t interval : {0u, 1u}) {
    TickLogFilter filter(interval, kSlowUs);
    for (std::uint64_t t = 0; t < 50; ++t) EXPECT_TRUE(filter.keep(quiet(t), 0, 0, 10.0));
    EXPECT_EQ(filter.left_out(), 0u);
  }
}

TEST(TickLogFilter, EveryKindOfEventKeepsItsTickAndOnlyThatTick) {
  struct Case {
    const char* what;
    void (*change)(TickReport&, std::uint64_t& overruns, std::uint64_t& missed, double& time_us);
    bool lasting;  // a change of state or counter: the ticks after it are quiet again
  };
  const std::vector<Case> cases = {
      {"a collision", [](TickReport& r, std::uint64_t&, std::uint64_t&, double&) { r.collisions = 1; }, false},
      {"a guard", [](TickReport& r, std::uint64_t&, std::uint64_t&, double&) { r.guards.fold_splits = 1; }, false},
      {"a slow tick", [](TickReport&, std::uint64_t&, std::uint64_t&, double& t) { t = kSlowUs; }, false},
      {"an overrun", [](TickReport&, std::uint64_t& o, std::uint64_t&, double&) { o = 1; }, true},
      {"a missed period", [](TickReport&, std::uint64_t&, std::uint64_t& m, double&) { m = 3; }, true},
      {"a fingertip dropped", [](TickReport& r, std::uint64_t&, std::uint64_t&, double&) { r.out_of_range = 1; }, true},
      {"the glove going stale",
       [](TickReport& r, std::uint64_t&, std::uint64_t&, double&) { r.glove = GloveState::kStale; }, true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    TickLogFilter filter(100, kSlowUs);
    ASSERT_TRUE(filter.keep(quiet(0), 0, 0, 10.0));
    for (std::uint64_t t = 1; t < 10; ++t) ASSERT_FALSE(filter.keep(quiet(t), 0, 0, 10.0));
    TickReport event = quiet(10);
    std::uint64_t overruns = 0, missed = 0;
    double time_us = 10.0;
    c.change(event, overruns, missed, time_us);
    EXPECT_TRUE(filter.keep(event, overruns, missed, time_us));
    // The next tick: a lasting change is the new normal, and a one-tick event is over.
    TickReport next = quiet(11);
    if (c.lasting) {
      std::uint64_t o = 0, m = 0;
      double t = 10.0;
      c.change(next, o, m, t);
      EXPECT_FALSE(filter.keep(next, o, m, t));
    } else {
      EXPECT_FALSE(filter.keep(next, 0, 0, 10.0));
    }
    EXPECT_EQ(filter.kept() + filter.left_out(), 12u);
  }
}

TEST(TickLogFilter, IntervalInTicksFollowsTheRate) {
  EXPECT_EQ(tick_log_interval(100.0, 1000.0), 100u);
  EXPECT_EQ(tick_log_interval(100.0, 50.0), 5u);
  EXPECT_EQ(tick_log_interval(0.0, 1000.0), 0u);
  EXPECT_EQ(tick_log_interval(0.2, 1000.0), 0u);  // below one tick: every tick
}

}  // namespace
}  // namespace sculpt::rt
