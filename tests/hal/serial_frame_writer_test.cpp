// The glove side (SerialFrameWriter) and the host side (SerialGloveSource, SerialHapticSink)
// end to end, in the arrangement of the hardware-in-the-loop test: two pseudo-terminal pairs,
// the writer on one slave, the host on the other, and a relay copying between the masters in
// both directions as the cable (or a USB-serial pair) would.

#include "sculpt/hal/serial_frame_writer.hpp"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "pty_pair.hpp"
#include "support/eventually.hpp"
#include "serial_glove_source.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "serial_haptic_sink.hpp"
#include "support/file_contents.hpp"

namespace sculpt::hal {
namespace {

using Bytes = std::vector<std::uint8_t>;

using testing_support::Pty;

// Copies bytes between two masters in both directions until destroyed: the wire.
class Relay {
 public:
  Relay(int a, int b) : thread_([this, a, b] { run(a, b); }) {}
  ~Relay() {
    stop_ = true;
    thread_.join();
  }
  std::uint64_t bytes() const { return bytes_; }

 private:
  void run(int a, int b) {
    std::uint8_t buffer[4096];
    while (!stop_) {
      pollfd fds[2] = {{a, POLLIN, 0}, {b, POLLIN, 0}};
      if (::poll(fds, 2, 10) <= 0) continue;
      for (int i = 0; i < 2; ++i) {
        if ((fds[i].revents & POLLIN) == 0) continue;
        const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
        if (n <= 0) continue;
        const int to = i == 0 ? b : a;
        for (ssize_t done = 0; done < n;) {
          const ssize_t w = ::write(to, buffer + done, static_cast<std::size_t>(n - done));
          if (w <= 0) break;
          done += w;
        }
        bytes_ += static_cast<std::uint64_t>(n);
      }
    }
  }

  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> bytes_{0};
  std::thread thread_;
};

using test::eventually;

using test::file_contents;

SerialConfig writer_config_for(const std::string& device) {
  SerialConfig c;
  c.device = device;
  c.reconnect_interval_ms = 20.0;
  return c;
}

GloveSample sample(std::uint32_t i) {
  GloveSample s;
  s.hand = static_cast<std::uint8_t>(i % 2);
  s.sequence = i / 2;  // per hand, and the hands alternate
  s.device_time_us = 12'500ull * i;
  if (i % 3 == 0) {
    s.kind = SampleKind::kAngles;
    for (std::size_t f = 0; f < kFingers; ++f)
      s.angles[f] = {0.1f * static_cast<float>(f), 0.2f, 0.3f, static_cast<float>(i)};
    s.wrist.position = {1.0f, 2.0f, static_cast<float>(i)};
    s.wrist.orientation = {0.0f, 1.0f, 0.0f, 0.0f};
  } else {
    s.kind = SampleKind::kPositions;
    for (std::size_t j = 0; j < kJointPoints; ++j) s.joints[j] = {static_cast<float>(j), -static_cast<float>(i), 0.25f};
  }
  return s;
}

HapticCommand command(std::uint32_t tick) {
  HapticCommand c;
  c.hand = 1;
  c.tick = tick;
  c.active_mask = static_cast<std::uint8_t>(tick & 0x1F);
  for (std::size_t f = 0; f < kFingers; ++f)
    c.force[f] = {0.5f * static_cast<float>(f), -1.0f, static_cast<float>(tick)};
  return c;
}

TEST(SerialFrameWriter, ThrowsNamingTheDevice) {
  try {
    SerialFrameWriter writer("/nonexistent/ttyGLOVE");
    FAIL() << "opened a device that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("serial /nonexistent/ttyGLOVE: open:"), std::string::npos) << e.what();
  }
  Pty pty;
  EXPECT_THROW(SerialFrameWriter(pty.slave_path(), 1234), std::invalid_argument);
}

TEST(SerialFrameWriter, EndToEndThroughTwoPtyPairsAndARelay) {
  Pty glove_side;  // the writer's device
  Pty host_side;   // the station's device
  Relay wire(glove_side.master(), host_side.master());

  SerialGloveSource source(writer_config_for(host_side.slave_path()), 1024);
  SerialHapticSink sink(writer_config_for(host_side.slave_path()), 64);
  source.start();
  sink.start();
  ASSERT_EQ(source.state(), SourceState::kConnected);
  ASSERT_TRUE(sink.connected());
  SerialFrameWriter writer(glove_side.slave_path());

  constexpr std::uint32_t kSamples = 300;
  for (std::uint32_t i = 0; i < kSamples; ++i) ASSERT_TRUE(writer.write_sample(sample(i))) << i;
  ASSERT_TRUE(eventually([&] { return source.counters().samples == kSamples; }))
      << source.counters().samples << " of " << kSamples;
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.crc_errors + c.framing_errors + c.sequence_gaps + c.overflows, 0u);

  // Haptics back from the station to the glove, one at a time (a burst would be coalesced to
  // its newest command: see the slow-line test below).
  constexpr std::uint32_t kCommands = 20;
  for (std::uint32_t t = 0; t < kCommands; ++t) {
    ASSERT_TRUE(sink.send(command(t)));
    ASSERT_TRUE(eventually([&] { return sink.frames_written() == t + 1; })) << t;
  }
  ASSERT_TRUE(eventually([&] { return writer.haptic_frames_received() == kCommands; }))
      << writer.haptic_frames_received();
  ASSERT_TRUE(writer.last_haptic().has_value());
  const HapticCommand& last = *writer.last_haptic();
  const HapticCommand expected = command(kCommands - 1);
  EXPECT_EQ(last.hand, expected.hand);
  EXPECT_EQ(last.tick, expected.tick);
  EXPECT_EQ(last.active_mask, expected.active_mask);
  EXPECT_EQ(last.force, expected.force);
  EXPECT_EQ(sink.frames_written(), kCommands);
  EXPECT_EQ(sink.dropped(), 0u);
  EXPECT_EQ(writer.input_counters().crc_errors + writer.input_counters().framing_errors, 0u);
  // The haptic frames also pass the source's own line (it shares the device): ignored there.
  EXPECT_EQ(source.counters().samples, kSamples);

  sink.stop();
  source.stop();
}

TEST(SerialFrameWriter, SamplesArriveIntactAndInOrder) {
  Pty glove_side;
  Pty host_side;
  Relay wire(glove_side.master(), host_side.master());
  SerialGloveSource source(writer_config_for(host_side.slave_path()), 1024);
  source.start();
  SerialFrameWriter writer(glove_side.slave_path());
  constexpr std::uint32_t kSamples = 120;
  for (std::uint32_t i = 0; i < kSamples; ++i) ASSERT_TRUE(writer.write_sample(sample(i)));

  std::vector<GloveSample> got;
  std::vector<GloveSample> buffer(32);
  ASSERT_TRUE(eventually([&] {
    const std::size_t n = source.poll(buffer);
    got.insert(got.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
    return got.size() >= kSamples;
  }));
  ASSERT_EQ(got.size(), kSamples);
  for (std::uint32_t i = 0; i < kSamples; ++i) {
    const GloveSample want = sample(i);
    ASSERT_EQ(got[i].sequence, i / 2);
    EXPECT_EQ(got[i].hand, want.hand);
    EXPECT_EQ(got[i].kind, want.kind);
    EXPECT_EQ(got[i].device_time_us, want.device_time_us);
    if (want.kind == SampleKind::kAngles) {
      EXPECT_EQ(got[i].angles, want.angles);
      EXPECT_EQ(got[i].wrist.position, want.wrist.position);
      EXPECT_EQ(got[i].wrist.orientation, want.wrist.orientation);
    } else {
      EXPECT_EQ(got[i].joints, want.joints);
    }
  }
}

TEST(SerialFrameWriter, ReportsADeviceThatIsGoneAndReopensIt) {
  char pattern[] = "/tmp/sculpt-writer-XXXXXX";
  ASSERT_NE(::mkdtemp(pattern), nullptr);
  const std::filesystem::path dir = pattern;
  const std::string link = (dir / "glove").string();
  auto first = std::make_unique<Pty>();
  std::filesystem::create_symlink(first->slave_path(), link);

  SerialFrameWriter writer(link);
  ASSERT_TRUE(writer.write_sample(sample(0)));
  first->close();
  bool ok = true;
  ASSERT_TRUE(eventually([&] {
    ok = writer.write_sample(sample(1));
    return !ok;
  }));
  EXPECT_FALSE(writer.is_open());
  EXPECT_FALSE(writer.write_sample(sample(2)));

  std::filesystem::remove(link);
  EXPECT_FALSE(writer.reopen());
  EXPECT_NE(writer.last_error().find(link), std::string::npos) << writer.last_error();

  Pty second;
  std::filesystem::create_symlink(second.slave_path(), link);
  ASSERT_TRUE(writer.reopen()) << writer.last_error();
  ASSERT_TRUE(writer.write_sample(sample(3)));
  // The bytes reach the new device's master.
  pollfd in{second.master(), POLLIN, 0};
  ASSERT_EQ(::poll(&in, 1, 5000), 1);
  std::uint8_t buffer[1024];
  EXPECT_GT(::read(second.master(), buffer, sizeof buffer), 0);
  std::filesystem::remove_all(dir);
}

TEST(SerialHapticSink, DropsCommandsWhileTheDeviceIsAbsentAndWritesOnceItIsBack) {
  char pattern[] = "/tmp/sculpt-sink-XXXXXX";
  ASSERT_NE(::mkdtemp(pattern), nullptr);
  const std::filesystem::path dir = pattern;
  const std::string link = (dir / "glove").string();

  SerialHapticSink sink(writer_config_for(link), 16);
  sink.start();
  EXPECT_FALSE(sink.connected());
  for (std::uint32_t t = 0; t < 5; ++t) EXPECT_TRUE(sink.send(command(t)));
  // A burst reaching the writer at once is coalesced to its newest command, which is dropped.
  ASSERT_TRUE(eventually([&] { return sink.dropped() + sink.superseded() == 5; })) << sink.dropped();
  const std::uint64_t dropped = sink.dropped();
  EXPECT_GE(dropped, 1u);

  Pty pty;
  std::filesystem::create_symlink(pty.slave_path(), link);
  ASSERT_TRUE(eventually([&] { return sink.connected(); }));
  ASSERT_TRUE(sink.send(command(99)));
  ASSERT_TRUE(eventually([&] { return sink.frames_written() == 1; }));

  // The frame on the wire is a haptic frame with the sink's sequence and the command.
  FrameDecoder decoder;
  std::vector<DecodedFrame> frames;
  ASSERT_TRUE(eventually([&] {
    pollfd in{pty.master(), POLLIN, 0};
    if (::poll(&in, 1, 0) == 1) {
      std::uint8_t buffer[512];
      const ssize_t n = ::read(pty.master(), buffer, sizeof buffer);
      if (n > 0) {
        decoder.feed(std::span<const std::uint8_t>(buffer, static_cast<std::size_t>(n)),
                     [&](const DecodedFrame& f) { frames.push_back(f); });
      }
    }
    return !frames.empty();
  }));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, DecodedFrame::Type::kHaptic);
  EXPECT_EQ(frames[0].sequence, 0u);  // the dropped commands were never framed
  EXPECT_EQ(frames[0].haptic.tick, 99u);
  EXPECT_EQ(frames[0].haptic.force, command(99).force);
  EXPECT_GT(frames[0].device_time_us, 0u);
  EXPECT_EQ(sink.dropped(), dropped);
  sink.stop();
  std::filesystem::remove_all(dir);
}

// A file where the glove's device should be would be written to as a glove: refused at start,
// as the glove source refuses it, naming the path.
TEST(SerialHapticSink, StartRefusesAPathThatIsNotADevice) {
  char pattern[] = "/tmp/sculpt-sink-XXXXXX";
  ASSERT_NE(::mkdtemp(pattern), nullptr);
  const std::filesystem::path dir = pattern;
  const std::string file = (dir / "plain.txt").string();
  std::ofstream(file) << "not a tty";
  SerialHapticSink sink(writer_config_for(file), 16);
  try {
    sink.start();
    ADD_FAILURE() << "start() accepted a regular file";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "serial haptic sink " + file + ": exists but is not a character device (a serial port or pty)");
  }
  EXPECT_EQ(file_contents(file), "not a tty") << "nothing was written to it";
  std::filesystem::remove_all(dir);
}

TEST(SerialHapticSink, CountsAFullQueueAsDropped) {
  // Not started: nothing drains the queue, so the third command does not fit (capacity 2).
  Pty pty;
  SerialHapticSink sink(writer_config_for(pty.slave_path()), 2);
  EXPECT_TRUE(sink.send(command(0)));
  EXPECT_TRUE(sink.send(command(1)));
  EXPECT_FALSE(sink.send(command(2)));
  EXPECT_EQ(sink.dropped(), 1u);
}

TEST(SerialHapticSink, ASlowLineCarriesTheNewestCommandAndNeverABacklog) {
  // Nobody reads the line at first, so the kernel's buffer fills and the writer stalls, as on
  // a line slower than the loop. The loop goes on sending at about 1 kHz; when the line drains,
  // what arrives is in tick order, far fewer frames than commands, and ends with the newest.
  Pty pty;
  SerialHapticSink sink(writer_config_for(pty.slave_path()), 256);
  sink.start();
  ASSERT_TRUE(sink.connected());
  constexpr std::uint32_t kCommands = 1500;
  std::uint32_t accepted = 0;
  for (std::uint32_t t = 0; t < kCommands; ++t) {
    accepted += sink.send(command(t));
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  std::vector<std::uint32_t> ticks;
  std::uint64_t in_contact = 0;  // frames on the line with a finger in contact (all hand 1)
  FrameDecoder decoder;
  std::array<std::uint8_t, 4096> buffer{};
  const auto read_line = [&] {
    for (;;) {
      pollfd in{pty.master(), POLLIN, 0};
      if (::poll(&in, 1, 0) <= 0) return;
      const ssize_t n = ::read(pty.master(), buffer.data(), buffer.size());
      if (n <= 0) return;
      decoder.feed(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)),
                   [&](const DecodedFrame& f) {
                     if (f.type != DecodedFrame::Type::kHaptic) return;
                     ticks.push_back(f.haptic.tick);
                     in_contact += f.haptic.active_mask != 0;
                   });
    }
  };
  // The line drains; one more command after the backlog must be the last to arrive. (Up to
  // 20 s: a loaded CI machine once took longer than 5 s here.)
  ASSERT_TRUE(eventually(
      [&] {
        read_line();
        return sink.frames_written() + sink.dropped() + sink.superseded() == accepted;
      },
      std::chrono::seconds(20)))
      << sink.frames_written() << " written + " << sink.dropped() << " dropped + " << sink.superseded()
      << " superseded of " << accepted << " accepted";
  ASSERT_TRUE(sink.send(command(kCommands)));
  ASSERT_TRUE(eventually([&] {
    read_line();
    return !ticks.empty() && ticks.back() == kCommands;
  })) << "the newest command never arrived";
  sink.stop();

  for (std::size_t i = 1; i < ticks.size(); ++i) ASSERT_GT(ticks[i], ticks[i - 1]) << "frame " << i;
  EXPECT_GT(sink.superseded(), 0u) << "the stalled line should have coalesced commands";
  EXPECT_LT(ticks.size(), static_cast<std::size_t>(kCommands));
  EXPECT_EQ(sink.frames_written() + sink.dropped() + sink.superseded(), accepted + 1u);
  EXPECT_EQ(ticks.size(), sink.frames_written());
  // What the hand felt: the frames with a contact, counted by the sink as the glove decodes them
  // (a command every 32nd tick rests; those, and the superseded, are not among them).
  EXPECT_EQ(sink.delivered_in_contact(1), in_contact);
  EXPECT_GT(in_contact, 0u);
  EXPECT_EQ(sink.delivered_in_contact(0), 0u);
  std::printf("[ serial ] %u commands: %zu frames on the line, %llu superseded, %llu dropped\n", kCommands + 1,
              ticks.size(), static_cast<unsigned long long>(sink.superseded()),
              static_cast<unsigned long long>(sink.dropped()));
}

// A pty has no driver buffer to ask about (TIOCOUTQ is always 0 there), and its reader's
// buffer fills through a kernel work queue that lags on a loaded machine. What waits on this
// line is counted as a UART driver would: the bytes the sink wrote (whole frames, all the same
// size) less those the glove end has read.
std::atomic<const SerialHapticSink*> line_sink{nullptr};
std::atomic<std::size_t> line_frame_bytes{0};
std::atomic<std::size_t> line_bytes_read{0};
std::size_t unread_on_line(int) noexcept {
  const SerialHapticSink* sink = line_sink.load();
  const std::size_t written = sink ? sink->frames_written() * line_frame_bytes.load() : 0;
  const std::size_t read = line_bytes_read.load();
  return written > read ? written - read : 0;
}

TEST(SerialHapticSink, KeepsTheLinesBacklogToAFrameSoCommandsArriveFresh) {
  // The glove reads one frame's worth every 5 ms, a line about 17 kB/s: far slower than the
  // loop's commands at 1 kHz. Without a bound on what waits in the driver, each frame would
  // queue behind about 4 KB (47 frames: a quarter of a second here, over a second seen); with
  // it, at most one frame is ahead of the one being written. Counted in frames and bytes, not
  // in time, so that a loaded machine's scheduling does not decide the result.
  Pty pty;
  std::array<std::uint8_t, kMaxFrameBytes> scratch{};
  line_frame_bytes = encode_haptic_frame(command(0), 0, 0, scratch);
  line_bytes_read = 0;
  SerialHapticSink sink(writer_config_for(pty.slave_path()), 256, &unread_on_line);
  line_sink = &sink;
  sink.start();
  ASSERT_TRUE(sink.connected());
  std::atomic<std::uint32_t> now_tick{0};
  std::atomic<bool> done{false};
  std::atomic<std::uint64_t> frames_read{0};
  std::uint64_t most_written_after = 0;
  std::uint32_t oldest = 0;
  std::size_t most_unread = 0;
  std::thread glove([&] {
    FrameDecoder decoder;
    std::array<std::uint8_t, 87> buffer{};
    while (!done.load()) {
      most_unread = std::max(most_unread, unread_on_line(0));
      pollfd in{pty.master(), POLLIN, 0};
      if (::poll(&in, 1, 5) > 0) {
        const ssize_t n = ::read(pty.master(), buffer.data(), buffer.size());
        if (n > 0) {
          line_bytes_read += static_cast<std::size_t>(n);
          decoder.feed(
              std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)), [&](const DecodedFrame& f) {
                if (f.type != DecodedFrame::Type::kHaptic) return;
                ++frames_read;
                // Frames the sink finished after this one: the queue it waited behind.
                // (The count may not yet include this frame itself, hence signed.)
                const auto after =
                    static_cast<std::int64_t>(sink.frames_written()) - static_cast<std::int64_t>(f.sequence) - 1;
                most_written_after = std::max<std::uint64_t>(
                    most_written_after, static_cast<std::uint64_t>(std::max<std::int64_t>(after, 0)));
                oldest = std::max(oldest, now_tick.load() - f.haptic.tick);
              });
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  // Until the glove has read enough to judge (about 1.5 s here; longer on a loaded machine).
  for (std::uint32_t t = 0; frames_read.load() < 300 && t < 30'000; ++t) {
    now_tick = t;
    sink.send(command(t));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  done = true;
  glove.join();
  sink.stop();
  line_sink = nullptr;
  ASSERT_GE(frames_read.load(), 300u) << "the glove read too few frames to judge";
  std::printf(
      "[ serial ] slow glove: %llu frames read, at most %llu written after the one read, %zu bytes unread, oldest %u "
      "ticks old, %llu superseded\n",
      static_cast<unsigned long long>(frames_read.load()), static_cast<unsigned long long>(most_written_after),
      most_unread, oldest, static_cast<unsigned long long>(sink.superseded()));
  EXPECT_LE(most_unread, 2 * SerialHapticSink::kMaxBacklogBytes);
  EXPECT_LE(most_written_after, 2u);
  EXPECT_GT(sink.superseded(), 0u);
}

}  // namespace
}  // namespace sculpt::hal
