// The serial glove source over a real pseudo-terminal: the test holds the master (the glove's
// end) and the source opens the slave through a symlink, so unplugging and replugging is
// closing the pty and re-pointing the link. Also the sequence tracker it counts gaps with.

#include "serial_glove_source.hpp"
#include "serial_haptic_sink.hpp"

#include <gtest/gtest.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "pty_pair.hpp"
#include "support/eventually.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "sequence_tracker.hpp"

namespace sculpt::hal {
namespace {

using Bytes = std::vector<std::uint8_t>;

using testing_support::Pty;

// A private directory holding the symlink the source opens, like a udev by-id link.
class LinkDir {
 public:
  LinkDir() {
    char pattern[] = "/tmp/sculpt-serial-XXXXXX";
    if (::mkdtemp(pattern) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = pattern;
  }
  ~LinkDir() { std::filesystem::remove_all(dir_); }
  std::string link() const { return (dir_ / "glove").string(); }
  /// Atomically (re)points the link at `target`.
  void point_at(const std::string& target) const {
    const auto tmp = dir_ / "glove.new";
    std::filesystem::remove(tmp);
    std::filesystem::create_symlink(target, tmp);
    std::filesystem::rename(tmp, link());
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

// Bounded wait: true as soon as `done` holds, false after `timeout`. The machine is shared and
// slow at times, so deadlines are generous and only catch outright failure.
using test::eventually;

// Polls the source until `count` samples have arrived or the deadline passes.
std::vector<GloveSample> receive(SerialGloveSource& source, std::size_t count) {
  std::vector<GloveSample> got;
  std::vector<GloveSample> buffer(64);
  eventually([&] {
    const std::size_t n = source.poll(buffer);
    got.insert(got.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
    return got.size() >= count;
  });
  return got;
}

GloveSample sample(std::uint8_t hand, std::uint32_t sequence) {
  GloveSample s;
  s.hand = hand;
  s.kind = SampleKind::kPositions;
  s.sequence = sequence;
  s.device_time_us = 1000ull * sequence;
  for (std::size_t j = 0; j < kJointPoints; ++j) {
    s.joints[j] = {0.01f * static_cast<float>(j), static_cast<float>(sequence), -0.5f};
  }
  return s;
}

Bytes frame(const GloveSample& s) {
  Bytes out(kMaxFrameBytes);
  out.resize(encode_sample_frame(s, out));
  return out;
}

// A frame whose CRC fails: the body is COBS-decoded, one CRC bit flipped and re-encoded, so
// the framing stays valid and only the checksum is wrong.
Bytes bad_crc_frame(const GloveSample& s) {
  const Bytes wire = frame(s);
  Bytes body;
  for (std::size_t i = 0; i + 1 < wire.size();) {
    const std::uint8_t code = wire[i++];
    for (int k = 1; k < code; ++k) body.push_back(wire[i++]);
    if (code != 0xFF && i + 1 < wire.size()) body.push_back(0);
  }
  body.back() ^= 0x01;
  Bytes out;
  std::size_t code_at = 0;
  out.push_back(0);
  for (const std::uint8_t b : body) {
    if (b == 0) {
      out[code_at] = static_cast<std::uint8_t>(out.size() - code_at);
      code_at = out.size();
      out.push_back(0);
    } else {
      out.push_back(b);
    }
  }
  out[code_at] = static_cast<std::uint8_t>(out.size() - code_at);
  out.push_back(0);
  return out;
}

SerialConfig config_for(const std::string& device) {
  SerialConfig c;
  c.device = device;
  c.baud = 921600;
  c.reconnect_interval_ms = 20.0;
  return c;
}

// ---- SequenceTracker -------------------------------------------------------------------------

TEST(SequenceTracker, CountsSkippedNumbersPerHand) {
  SequenceTracker t;
  EXPECT_EQ(t.observe(0, 10), 0u);  // first: nothing to compare with
  EXPECT_EQ(t.observe(1, 500), 0u);
  EXPECT_EQ(t.observe(0, 11), 0u);
  EXPECT_EQ(t.observe(0, 14), 2u);
  EXPECT_EQ(t.observe(1, 501), 0u);  // hands are independent
  EXPECT_EQ(t.observe(1, 511), 9u);
  EXPECT_EQ(t.observe(0, 14), 0u);  // a repeat is not a gap
  EXPECT_EQ(t.gaps(), 11u);
}

TEST(SequenceTracker, WrapsAroundAndTreatsABackwardsJumpAsARestart) {
  SequenceTracker t;
  t.observe(0, 0xFFFFFFFEu);
  EXPECT_EQ(t.observe(0, 0xFFFFFFFFu), 0u);
  EXPECT_EQ(t.observe(0, 0u), 0u);  // wrap, in order
  EXPECT_EQ(t.observe(0, 2u), 1u);
  EXPECT_EQ(t.observe(0, 1000000u), 999997u);
  EXPECT_EQ(t.observe(0, 0u), 0u);  // the device restarted its counter (e.g. replugged)
  EXPECT_EQ(t.observe(0, 1u), 0u);
  EXPECT_EQ(t.observe(7, 5u), 0u);  // no such hand: ignored
  EXPECT_EQ(t.gaps(), 1u + 999997u);
  t.reset();
  EXPECT_EQ(t.gaps(), 0u);
  EXPECT_EQ(t.observe(0, 50u), 0u);
}

// ---- configuration ---------------------------------------------------------------------------

TEST(SerialGloveSource, RejectsBadConfigurationNamingTheField) {
  auto message_of = [](const SerialConfig& c, std::size_t capacity) -> std::string {
    try {
      SerialGloveSource s(c, capacity);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  SerialConfig c = config_for("/dev/ttyGLOVE");
  c.baud = 12345;
  EXPECT_NE(message_of(c, 16).find("/dev/ttyGLOVE: baud 12345 is not a standard rate"), std::string::npos);
  c = config_for("");
  EXPECT_NE(message_of(c, 16).find("device path is empty"), std::string::npos);
  c = config_for("/dev/ttyGLOVE");
  c.reconnect_interval_ms = 0.0;
  EXPECT_NE(message_of(c, 16).find("reconnect_interval_ms"), std::string::npos);
  EXPECT_NE(message_of(config_for("/dev/ttyGLOVE"), 0).find("queue_capacity"), std::string::npos);
}

TEST(SerialGloveSource, StartRefusesAPathThatIsNotADevice) {
  LinkDir dir;
  const std::string file = (dir.dir() / "plain.txt").string();
  std::ofstream(file) << "not a tty";
  SerialGloveSource source(config_for(file), 16);
  try {
    source.start();
    FAIL() << "start() accepted a regular file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file + ": exists but is not a character device"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

TEST(SerialGloveSource, ASecondReaderOfTheSameDeviceIsRefusedNamingIt) {
  // Two stations on one glove would each read part of its bytes (both then count CRC errors
  // and drop samples, and neither says why): the reader holds the device's lock, as pyserial's
  // exclusive mode takes it, and a second reader's start() stops naming the device. The haptic
  // sink, which writes on its own descriptor beside the source, takes no lock.
  Pty pty;
  SerialGloveSource first(config_for(pty.slave_path()), 16);
  first.start();
  ASSERT_EQ(first.state(), SourceState::kConnected);
  SerialGloveSource second(config_for(pty.slave_path()), 16);
  try {
    second.start();
    FAIL() << "a second reader started on " << pty.slave_path();
  } catch (const SerialPort::InUse& e) {
    EXPECT_NE(std::string(e.what()).find("serial " + pty.slave_path() + ": another program has it open"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(second.state(), SourceState::kStopped);
  SerialHapticSink sink(config_for(pty.slave_path()), 16);
  sink.start();
  EXPECT_TRUE(sink.connected());
  sink.stop();
  // The lock goes with the first reader's descriptor: the second starts once it has stopped, and
  // reads the glove.
  first.stop();
  second.start();
  EXPECT_EQ(second.state(), SourceState::kConnected);
  pty.write(frame(sample(0, 1)));
  EXPECT_EQ(receive(second, 1).size(), 1u);
}

// ---- traffic ---------------------------------------------------------------------------------

TEST(SerialGloveSource, DeliversSamplesInOrderWithReceiveTimes) {
  Pty pty;
  SerialGloveSource source(config_for(pty.slave_path()), 256);
  source.start();
  EXPECT_EQ(source.state(), SourceState::kConnected);  // the device was there: connected at once
  std::vector<GloveSample> sent;
  for (std::uint32_t i = 0; i < 40; ++i) sent.push_back(sample(static_cast<std::uint8_t>(i % 2), i / 2));
  for (const GloveSample& s : sent) pty.write(frame(s));

  const std::vector<GloveSample> got = receive(source, sent.size());
  ASSERT_EQ(got.size(), sent.size());
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  const std::int64_t now_ns = now.tv_sec * 1'000'000'000ll + now.tv_nsec;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(got[i].hand, sent[i].hand);
    EXPECT_EQ(got[i].sequence, sent[i].sequence);
    EXPECT_EQ(got[i].device_time_us, sent[i].device_time_us);
    EXPECT_EQ(got[i].joints, sent[i].joints);
    EXPECT_GT(got[i].receive_time_ns, 0);
    EXPECT_LE(got[i].receive_time_ns, now_ns);
    if (i > 0) {
      EXPECT_GE(got[i].receive_time_ns, got[i - 1].receive_time_ns);
    }
  }
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, sent.size());
  EXPECT_EQ(c.crc_errors + c.framing_errors + c.sequence_gaps + c.overflows, 0u);
  EXPECT_EQ(c.disconnects + c.reconnects, 0u);
  source.stop();
  EXPECT_EQ(source.state(), SourceState::kStopped);
  source.stop();  // idempotent
}

TEST(SerialGloveSource, CountsEachFaultByKindWhileSamplesKeepFlowing) {
  Pty pty;
  SerialGloveSource source(config_for(pty.slave_path()), 256);
  source.start();
  std::mt19937 rng(31);
  Bytes garbage(97);
  for (std::uint8_t& b : garbage) b = static_cast<std::uint8_t>(1 + rng() % 255);
  garbage.push_back(0);
  const Bytes whole = frame(sample(0, 2));
  Bytes truncated(whole.begin(), whole.begin() + 120);
  truncated.push_back(0);
  HapticCommand haptic;
  haptic.hand = 0;
  Bytes haptic_frame(kMaxFrameBytes);
  haptic_frame.resize(encode_haptic_frame(haptic, 0, 0, haptic_frame));

  pty.write(frame(sample(0, 0)));
  pty.write(garbage);  // framing error 1
  pty.write(frame(sample(0, 1)));
  pty.write(truncated);  // framing error 2
  pty.write(frame(sample(0, 2)));
  pty.write(bad_crc_frame(sample(0, 3)));  // crc error 1 (and sequence 3 is lost)
  pty.write(frame(sample(0, 4)));
  pty.write(haptic_frame);  // not for us: ignored, counted nowhere
  pty.write(frame(sample(0, 5)));

  const std::vector<GloveSample> got = receive(source, 5);
  ASSERT_EQ(got.size(), 5u);
  const std::uint32_t expected_sequences[] = {0, 1, 2, 4, 5};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(got[i].sequence, expected_sequences[i]);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 5u);
  EXPECT_EQ(c.framing_errors, 2u);
  EXPECT_EQ(c.crc_errors, 1u);
  EXPECT_EQ(c.sequence_gaps, 1u);  // the sample whose CRC failed is missing by number
  EXPECT_EQ(c.overflows, 0u);
}

TEST(SerialGloveSource, CountsSequenceGapsPerHand) {
  Pty pty;
  SerialGloveSource source(config_for(pty.slave_path()), 256);
  source.start();
  const std::pair<std::uint8_t, std::uint32_t> script[] = {
      {0, 0}, {0, 1}, {1, 70}, {0, 4}, {1, 71}, {1, 75}, {0, 5}, {0, 0} /* restart */, {0, 1}};
  for (const auto& [hand, seq] : script) pty.write(frame(sample(hand, seq)));
  ASSERT_EQ(receive(source, std::size(script)).size(), std::size(script));
  EXPECT_EQ(source.counters().sequence_gaps, 2u + 3u);
}

TEST(SerialGloveSource, CountsOverflowsWhenTheLoopDoesNotPoll) {
  Pty pty;
  SerialGloveSource source(config_for(pty.slave_path()), 2);
  source.start();
  for (std::uint32_t i = 0; i < 12; ++i) pty.write(frame(sample(0, i)));
  ASSERT_TRUE(eventually([&] {
    const SourceCounters c = source.counters();
    return c.samples + c.overflows == 12;
  }));
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 2u);
  EXPECT_EQ(c.overflows, 10u);
  std::vector<GloveSample> out(16);
  ASSERT_EQ(source.poll(out), 2u);
  EXPECT_EQ(out[0].sequence, 0u);  // the oldest are kept; the ones that did not fit are dropped
  EXPECT_EQ(out[1].sequence, 1u);
  EXPECT_EQ(source.poll(out), 0u);
}

// ---- plugging and unplugging -------------------------------------------------------------------

TEST(SerialGloveSource, PicksUpAGlovePluggedInAfterStart) {
  LinkDir dir;
  SerialGloveSource source(config_for(dir.link()), 64);
  source.start();  // nothing there yet: not an error
  EXPECT_EQ(source.state(), SourceState::kConnecting);
  EXPECT_NE(source.last_error().find(dir.link()), std::string::npos) << source.last_error();

  Pty pty;
  dir.point_at(pty.slave_path());
  ASSERT_TRUE(eventually([&] { return source.state() == SourceState::kConnected; }));
  pty.write(frame(sample(1, 9)));
  const auto got = receive(source, 1);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].sequence, 9u);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.disconnects, 0u);  // the first connection is not a reconnect
  EXPECT_EQ(c.reconnects, 0u);
  EXPECT_TRUE(source.last_error().empty());
}

TEST(SerialGloveSource, ReconnectsToTheSamePathAfterTheDeviceDisappears) {
  LinkDir dir;
  auto first = std::make_unique<Pty>();
  dir.point_at(first->slave_path());
  SerialGloveSource source(config_for(dir.link()), 64);
  source.start();
  ASSERT_EQ(source.state(), SourceState::kConnected);
  for (std::uint32_t i = 0; i < 3; ++i) first->write(frame(sample(0, 100 + i)));
  ASSERT_EQ(receive(source, 3).size(), 3u);

  // Unplug: the pty goes away, its /dev/pts entry with it, and the link dangles.
  first->close();
  ASSERT_TRUE(
      eventually([&] { return source.state() == SourceState::kDisconnected && source.counters().disconnects == 1; }));

  // Replug: a new device node (perhaps another number) behind the same link.
  Pty second;
  dir.point_at(second.slave_path());
  ASSERT_TRUE(eventually([&] { return source.counters().reconnects == 1; }));
  EXPECT_EQ(source.state(), SourceState::kConnected);
  // The glove restarted its counter: a backwards jump, not four billion lost samples.
  for (std::uint32_t i = 0; i < 3; ++i) second.write(frame(sample(0, i)));
  const auto got = receive(source, 3);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].sequence, 0u);
  EXPECT_EQ(got[2].sequence, 2u);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.disconnects, 1u);
  EXPECT_EQ(c.reconnects, 1u);
  EXPECT_EQ(c.samples, 6u);
  EXPECT_EQ(c.sequence_gaps, 0u);
  EXPECT_EQ(c.framing_errors + c.crc_errors, 0u);
}

TEST(SerialGloveSource, StopsPromptlyWhileWaitingForADevice) {
  LinkDir dir;
  SerialConfig config = config_for(dir.link());
  config.reconnect_interval_ms = 60'000.0;  // a stop must not wait out the retry interval
  SerialGloveSource source(config, 8);
  source.start();
  const auto t0 = std::chrono::steady_clock::now();
  source.stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));  // gross failure only
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

}  // namespace
}  // namespace sculpt::hal
