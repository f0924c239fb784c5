// SimGloveSource: the script's stream delivered in real time through the queue, with
// overflows and dropouts counted. Time is only checked as a lower bound (a sample is never
// early) or for gross failure.

#include "sim_glove_source.hpp"

#include <gtest/gtest.h>

#include <time.h>

#include <chrono>
#include <thread>
#include <vector>

namespace sculpt::hal {
namespace {

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

SimConfig script(double rate_hz, double duration_s) {
  SimConfig c;
  c.rate_hz = rate_hz;
  c.duration_s = duration_s;
  c.fingers.push_back(FingerScript{0, 1, {{0, 0, 0, 0}, {duration_s, 1, 0, 0}}});
  return c;
}

// Polls until the script is over (or 10 s, a gross failure), collecting every sample.
std::vector<GloveSample> drain(SimGloveSource& source) {
  std::vector<GloveSample> got;
  std::array<GloveSample, 16> buffer;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    const bool done = source.finished();
    const std::size_t n = source.poll(buffer);
    got.insert(got.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
    if (done && n == 0) break;
    if (std::chrono::steady_clock::now() > give_up) {
      ADD_FAILURE() << "the script did not finish within 10 s";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return got;
}

TEST(SimGloveSource, DeliversTheScriptInOrderAndNeverEarly) {
  SimGloveSource source(script(200, 0.25));
  EXPECT_EQ(source.state(), SourceState::kStopped);
  EXPECT_STREQ(source.name(), "sim");
  const std::int64_t before = now_ns();
  source.start();
  EXPECT_EQ(source.state(), SourceState::kConnected);
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 51u);
  SimScript reference(script(200, 0.25));
  for (std::size_t i = 0; i < got.size(); ++i) {
    GloveSample expected;
    ASSERT_TRUE(reference.next(expected));
    EXPECT_EQ(got[i].sequence, expected.sequence);
    EXPECT_EQ(got[i].joints, expected.joints);
    EXPECT_GE(got[i].receive_time_ns, before + static_cast<std::int64_t>(got[i].device_time_us) * 1000);
  }
  // A finished script is a glove that stopped sending: still "connected".
  EXPECT_TRUE(source.finished());
  EXPECT_EQ(source.state(), SourceState::kConnected);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 51u);
  EXPECT_EQ(c.overflows, 0u);
  EXPECT_EQ(c.sequence_gaps, 0u);
  source.stop();
  EXPECT_EQ(source.state(), SourceState::kStopped);
  source.stop();  // idempotent
}

TEST(SimGloveSource, CountsOverflowsWhenNobodyPolls) {
  SimGloveSource source(script(1000, 0.05), 4);
  source.start();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!source.finished() && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(source.finished());
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 4u);
  EXPECT_EQ(c.overflows, 51u - 4u);
  std::array<GloveSample, 8> out;
  ASSERT_EQ(source.poll(out), 4u);
  EXPECT_EQ(out[0].sequence, 0u);  // the oldest were kept, the newest dropped
  EXPECT_EQ(out[3].sequence, 3u);
}

TEST(SimGloveSource, DropoutsAreCountedAsSequenceGaps) {
  SimConfig c = script(1000, 0.2);
  c.dropout_probability = 0.25;
  c.seed = 3;
  SimGloveSource source(c);
  source.start();
  const auto got = drain(source);
  ASSERT_FALSE(got.empty());
  const SourceCounters counters = source.counters();
  EXPECT_EQ(counters.samples, got.size());
  EXPECT_EQ(counters.sequence_gaps, got.back().sequence + 1 - got.size());
  EXPECT_GT(counters.sequence_gaps, 0u);
}

TEST(SimGloveSource, LatencyDelaysDelivery) {
  SimConfig c = script(100, 0.0);
  c.fingers[0].keyframes = {{0, 0, 0, 0}};
  c.latency_ms = 100;
  SimGloveSource source(c);
  const std::int64_t before = now_ns();
  source.start();
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_GE(got[0].receive_time_ns - before, 100'000'000);
}

TEST(SimGloveSource, StopIsPromptAndRestartReplaysTheScript) {
  SimGloveSource source(script(10, 100.0));  // 100 s of samples
  source.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto t0 = std::chrono::steady_clock::now();
  source.stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2));
  std::array<GloveSample, 4> out;
  ASSERT_EQ(source.poll(out), 1u);  // the sample at device time 0
  source.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  source.stop();
  ASSERT_EQ(source.poll(out), 1u);
  EXPECT_EQ(out[0].sequence, 0u);
}

}  // namespace
}  // namespace sculpt::hal
