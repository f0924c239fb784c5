// ReplayGloveSource: a re-run's ticks take the samples the live loop's ticks took together, so
// that the loop, which keeps only a hand's newest sample of a tick, sees what it saw live.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "sculpt/rt/replay_glove_source.hpp"

namespace sculpt::rt {
namespace {

constexpr std::int64_t kMs = 1'000'000;

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

}  // namespace
}  // namespace sculpt::rt
