// ReplayGloveSource: a re-run's ticks take the samples the live loop's ticks took together, so
// that the loop, which keeps only a hand's newest sample of a tick, sees what it saw live.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "sculpt/rt/replay_glove_source.hpp"
#include "support/nanoseconds.hpp"

namespace sculpt::rt {
namespace {

using test::kMs;

hal::GloveSample sample(std::uint32_t sequence, std::int64_t receive_ns) {
  hal::GloveSample s;
  s.sequence = sequence;
  s.receive_time_ns = receive_ns;
  return s;
}

// The sequence numbers each tick takes, ticks at first_time_ns() + k ms.
std::vector<std::vector<std::uint32_t>> ticks_taken(ReplayGloveSource& source, int ticks) {
  std::vector<std::vector<std::uint32_t>> out;
  std::array<hal::GloveSample, 2> inbox;  // smaller than a live tick's samples: polled again
  for (int k = 0; k < ticks; ++k) {
    source.set_now(source.first_time_ns() + k * kMs);
    std::vector<std::uint32_t>& taken = out.emplace_back();
    for (std::size_t n = source.poll(inbox); n > 0; n = n == inbox.size() ? source.poll(inbox) : 0) {
      for (std::size_t i = 0; i < n; ++i) taken.push_back(inbox[i].sequence);
    }
  }
  return out;
}

using Ticks = std::vector<std::vector<std::uint32_t>>;

// Live, a tick took samples 1-3 (queued while the loop was late), the next took 4 and 5 which
// arrived 0.2 ms apart, the next 6. By receive time, a tick grid starting at sample 1 splits
// those groups differently; by the log's ticks each re-run tick takes one live tick's samples,
// once the last of them has arrived.
TEST(ReplayGloveSource, EachTickTakesOneLiveTicksSamplesOnceTheyHaveAllArrived) {
  SampleLog log;
  log.samples = {sample(1, 0),         sample(2, 300'000),   sample(3, 1'900'000),
                 sample(4, 2'100'000), sample(5, 2'300'000), sample(6, 2'400'000)};
  log.taken = {0, 0, 0, 1, 1, 2};
  ReplayGloveSource source(log);
  EXPECT_EQ(source.last_time_ns(), 2'400'000);
  EXPECT_EQ(ticks_taken(source, 6), (Ticks{{}, {}, {1, 2, 3}, {4, 5}, {6}, {}}));
  EXPECT_TRUE(source.finished());

  // Without the log's ticks, by receive time: every sample due, in receive order.
  log.taken.clear();
  std::swap(log.samples[0], log.samples[2]);  // out of order in the file
  ReplayGloveSource by_time(log);
  EXPECT_EQ(ticks_taken(by_time, 4), (Ticks{{1}, {2}, {3}, {4, 5, 6}}));
}

// After a crash the last samples were never followed by their tick's events: they go by
// receive time, after the named ticks and never in the same re-run tick as one of them.
TEST(ReplayGloveSource, ACrashsUnnamedTailGoesByReceiveTimeAfterTheNamedTicks) {
  SampleLog log;
  log.samples = {sample(1, 0), sample(2, 500'000), sample(4, 1'300'000), sample(3, 1'200'000)};
  log.taken = {0, 1, -1, -1};
  ReplayGloveSource source(log);
  EXPECT_EQ(source.last_time_ns(), 1'300'000);
  EXPECT_EQ(ticks_taken(source, 4), (Ticks{{1}, {2}, {3, 4}, {}}));
}

// Across a gap longer than the glove's timeout the quiet ticks change nothing: the clock skips
// to the last tick before the next sample, on the same grid, so that sample is taken at the
// virtual time it would have been without the skip.
TEST(ReplayGloveSource, AGapsQuietTicksAreSkippedOnTheSameGrid) {
  SampleLog log;
  log.samples = {sample(1, 0), sample(2, 1 * kMs), sample(3, 10'000 * kMs + 300'000), sample(4, 10'001 * kMs)};
  log.taken = {0, 1, 2, 3};
  ReplayGloveSource source(log);
  const std::int64_t idle = 102 * kMs;  // a 100 ms timeout and two periods
  std::array<hal::GloveSample, 4> inbox;
  std::vector<std::int64_t> taken_at;
  int ticks = 0;
  for (std::int64_t t = source.first_time_ns(); t <= source.last_time_ns() + 5 * kMs;
       t = source.next_tick_ns(t, kMs, idle)) {
    source.set_now(t);
    ++ticks;
    for (std::size_t k = 0, n = source.poll(inbox); k < n; ++k) taken_at.push_back(t);
    ASSERT_LT(ticks, 1000) << "the gap was not skipped";
  }
  EXPECT_EQ(taken_at, (std::vector<std::int64_t>{0, 1 * kMs, 10'001 * kMs, 10'002 * kMs}));
  EXPECT_LT(ticks, 115);  // the quiet 102 ms after sample 2, then the last samples' ticks and five more
  // Until no sample has come for `idle`, no tick is skipped; then the next is the grid's last
  // tick before the next sample is due (10,000.3 ms: the tick at 10,001 ms takes it).
  ReplayGloveSource fresh(log);
  for (const std::int64_t t : {std::int64_t{0}, kMs}) {
    fresh.set_now(t);
    ASSERT_EQ(fresh.poll(inbox), 1u);
  }
  EXPECT_EQ(fresh.next_tick_ns(50 * kMs, kMs, idle), 51 * kMs);
  EXPECT_EQ(fresh.next_tick_ns(101 * kMs, kMs, idle), 102 * kMs);
  EXPECT_EQ(fresh.next_tick_ns(102 * kMs, kMs, idle), 10'000 * kMs);
}

}  // namespace
}  // namespace sculpt::rt
