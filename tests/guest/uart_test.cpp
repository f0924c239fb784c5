// The serial backends on real serial drivers, where the host tests have only ptys: the Linux
// 8250 driver and its serial core on qemu's 16550A (a pty keeps no count of unsent bytes, so
// the host tests give the sink a stand-in for TIOCOUTQ; it ignores flow control; it makes any
// rate), and an FTDI USB-serial adapter (ftdi_sio) cabled to another UART, unplugged and
// plugged in. tests/guest/uart.sh names the devices in GLOVE_UART and GLOVE_ADAPTER*.
//
// On the UART the test's own descriptor plays the glove: in the UART's loopback mode
// (TIOCM_LOOP) its CTS input is its own RTS output, so with RTS low and CTS flow control on
// (CRTSCTS) the driver holds what is written, as behind a glove that is not reading; with flow
// control off the bytes go out at once and come back in on the receiver, where the test decodes
// the frames that reached the wire (or the source reads what the test wrote). Skips, saying
// so, anywhere else.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "sculpt/hal/frame_codec.hpp"
#include "serial_glove_source.hpp"
#include "serial_haptic_sink.hpp"
#include "support/eventually.hpp"

namespace sculpt::hal {
namespace {

// The modem-control bit that puts a UART in loopback (the kernel's asm-generic/termios.h, which
// cannot be included beside glibc's <termios.h>; the serial core passes it to the 8250's MCR).
constexpr int kLoopback = 0x8000;  // TIOCM_LOOP

std::string uart_path() {
  const char* path = std::getenv("GLOVE_UART");
  return path != nullptr ? path : "";
}

// A guest under software emulation is slow: ten seconds unless told.
bool eventually(const std::function<bool()>& done, std::chrono::seconds timeout = std::chrono::seconds(10)) {
  return test::eventually(done, timeout);
}

HapticCommand command(std::uint32_t tick) {
  HapticCommand c;
  c.hand = 0;
  c.tick = tick;
  c.active_mask = 0x1F;
  for (std::size_t f = 0; f < kFingers; ++f) c.force[f] = {0.25f * static_cast<float>(f), -1.0f, 1e-3f * tick};
  return c;
}

// Frame i of a glove sending positions: `hand`'s sample `sequence`, its last joint's y i / 1000.
GloveSample positions(std::uint8_t hand, std::uint32_t sequence, std::uint32_t i) {
  GloveSample s;
  s.hand = hand;
  s.kind = SampleKind::kPositions;
  s.sequence = sequence;
  s.device_time_us = 1000ull * i;
  for (std::size_t j = 0; j < kJointPoints; ++j) s.joints[j] = {0.01f * static_cast<float>(j), 1e-3f * i, -0.5f};
  return s;
}

// The test's descriptor on the UART: stalls and releases its line and reads what it sent.
class Line {
 public:
  explicit Line(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC)) {}
  ~Line() {
    if (fd_ < 0) return;
    set_flow_control(false);
    int loop = kLoopback;
    ::ioctl(fd_, TIOCMBIC, &loop);
    ::close(fd_);
  }
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;

  bool open() const { return fd_ >= 0; }

  // Raw: no echo (every byte received would otherwise go out again), no line editing.
  bool make_raw(speed_t speed = B115200) {
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) return false;
    ::cfmakeraw(&tio);
    tio.c_cflag |= CLOCAL | CREAD;
    ::cfsetspeed(&tio, speed);
    return ::tcsetattr(fd_, TCSANOW, &tio) == 0;
  }
  // Raw, loopback, RTS low: the line is then held whenever CTS flow control is on.
  bool loop_back() {
    if (!make_raw()) return false;
    int loop = kLoopback, rts = TIOCM_RTS;
    return ::ioctl(fd_, TIOCMBIS, &loop) == 0 && ::ioctl(fd_, TIOCMBIC, &rts) == 0;
  }
  // The serial core samples CTS when CRTSCTS changes: on, it finds CTS low and stops sending;
  // off, it sends what waits.
  bool set_flow_control(bool on) {
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) return false;
    tio.c_cflag = on ? (tio.c_cflag | CRTSCTS) : (tio.c_cflag & ~tcflag_t{CRTSCTS});
    return ::tcsetattr(fd_, TCSANOW, &tio) == 0;
  }
  bool hold() { return set_flow_control(true); }
  // Software flow control of the input, as a terminal program may leave it.
  bool set_input_flow_control() {
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) return false;
    tio.c_iflag |= IXOFF;
    return ::tcsetattr(fd_, TCSANOW, &tio) == 0;
  }
  termios settings() const {
    termios tio{};
    ::tcgetattr(fd_, &tio);
    return tio;
  }
  bool release() { return set_flow_control(false); }

  // Bytes written to the UART and not yet sent (what the sink's probe reads too).
  int unsent() const {
    int pending = -1;
    return ::ioctl(fd_, TIOCOUTQ, &pending) == 0 ? pending : -1;
  }

  // Writes every byte, waiting for room in the driver as a glove's UART would.
  bool write_all(std::span<const std::uint8_t> bytes) const {
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n > 0) {
        done += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno != EAGAIN) return false;
      pollfd out{fd_, POLLOUT, 0};
      if (::poll(&out, 1, 1000) <= 0) return false;
    }
    return true;
  }

  // Writes the sample's frame, whole.
  bool write_sample(const GloveSample& sample) const {
    std::array<std::uint8_t, kMaxFrameBytes> wire{};
    return write_all(std::span<const std::uint8_t>(wire.data(), encode_sample_frame(sample, wire)));
  }

  // Appends what the receiver has to `bytes`; returns how many.
  std::size_t read_into(std::vector<std::uint8_t>& bytes) const {
    std::size_t total = 0;
    std::array<std::uint8_t, 1024> buffer{};
    for (;;) {
      const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
      if (n <= 0) return total;
      bytes.insert(bytes.end(), buffer.begin(), buffer.begin() + n);
      total += static_cast<std::size_t>(n);
    }
  }

 private:
  int fd_;
};

// The haptic frames that reached the wire, decoded from what the line's receiver got.
struct Wire {
  void read(const Line& line) {
    bytes.clear();
    line.read_into(bytes);
    decoder.feed(std::span<const std::uint8_t>(bytes.data(), bytes.size()), [&](const DecodedFrame& f) {
      if (f.type != DecodedFrame::Type::kHaptic) return;
      ticks.push_back(f.haptic.tick);
      sequences.push_back(f.sequence);
    });
  }
  bool ends_with(std::uint32_t tick) const { return !ticks.empty() && ticks.back() == tick; }
  // Every frame whole (no CRC or framing error) and the frames in the order written.
  void expect_whole_and_in_order() const {
    EXPECT_EQ(decoder.counters().crc_errors, 0u);
    EXPECT_EQ(decoder.counters().framing_errors, 0u);
    for (std::size_t i = 1; i < ticks.size(); ++i) EXPECT_GT(ticks[i], ticks[i - 1]) << "frame " << i;
  }

  FrameDecoder decoder;
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint32_t> ticks, sequences;
};

class Uart : public ::testing::Test {
 protected:
  void SetUp() override {
    if (uart_path().empty()) GTEST_SKIP() << "no UART here (GLOVE_UART unset; scripts/guest_test.sh uart)";
    config_.device = uart_path();
    config_.baud = 115200;  // a 16550A's fastest at its 1.8432 MHz clock
    config_.reconnect_interval_ms = 20.0;
  }

  // The sink started on the UART, then the line held from the test's descriptor (after the
  // sink's own settings of the same terminal, which would undo the test's).
  void start_sink_on_held_line() {
    line_ = std::make_unique<Line>(uart_path());
    ASSERT_TRUE(line_->open()) << uart_path();
    sink_ = std::make_unique<SerialHapticSink>(config_, 1024);
    sink_->start();
    ASSERT_TRUE(sink_->connected());
    ASSERT_TRUE(line_->loop_back());
    ASSERT_TRUE(line_->hold());
  }

  // Releases the line, reads the wire until the frame of tick `newest` is on it, stops the sink
  // and reads what is left.
  void release_until(Wire& wire, std::uint32_t newest) {
    ASSERT_TRUE(line_->release());
    ASSERT_TRUE(eventually([&] {
      wire.read(*line_);
      return wire.ends_with(newest);
    })) << "the newest command never reached the wire ("
        << wire.ticks.size() << " frames)";
    sink_->stop();
    wire.read(*line_);
  }

  SerialConfig config_;
  std::unique_ptr<Line> line_;
  std::unique_ptr<SerialHapticSink> sink_;
};

TEST_F(Uart, AHeldLineKeepsWhatIsWrittenAndAReleasedOneSendsItBack) {
  // What the sink tests below rely on: the stall is real (the driver counts the bytes it holds
  // in TIOCOUTQ) and a release sends every byte, in order, onto the receiver.
  Line line(uart_path());
  ASSERT_TRUE(line.open()) << uart_path();
  ASSERT_TRUE(line.loop_back());
  ASSERT_TRUE(line.hold());
  const int writer = ::open(uart_path().c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  ASSERT_GE(writer, 0);
  std::vector<std::uint8_t> sent(1000);
  for (std::size_t i = 0; i < sent.size(); ++i) sent[i] = static_cast<std::uint8_t>(i * 7 + 3);
  ASSERT_EQ(::write(writer, sent.data(), sent.size()), static_cast<ssize_t>(sent.size()));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  // A 16550A may have taken up to its 16-byte FIFO before the stop.
  EXPECT_GE(line.unsent(), static_cast<int>(sent.size()) - 16);
  std::vector<std::uint8_t> received;
  line.read_into(received);
  EXPECT_LE(received.size(), 16u);
  ASSERT_TRUE(line.release());
  EXPECT_TRUE(eventually([&] {
    line.read_into(received);
    return received.size() >= sent.size();
  })) << received.size()
      << " of " << sent.size() << " bytes came back";
  EXPECT_EQ(line.unsent(), 0);
  EXPECT_EQ(received, sent);
  ::close(writer);
}

TEST_F(Uart, ARateTheUartCannotMakeStopsTheStartNamingBothRates) {
  // A 16550A makes at most 115,200 baud from its 1.8432 MHz clock. Asked for 921,600 (the
  // backends' default, which a USB-serial adapter makes), Linux's serial core keeps another rate
  // and tcsetattr still succeeds: without reading the rate back, the sink would drive the hand
  // over a line eight times slower than configured (or the source read the glove's bytes at the
  // wrong rate, as noise), and nothing would say why.
  SerialConfig fast = config_;
  fast.baud = 921600;
  const auto expect_refused = [](auto& backend) {
    try {
      backend.start();
      ADD_FAILURE() << "started at a rate the UART cannot make";
    } catch (const SerialPort::RateRefused& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(uart_path()), std::string::npos) << what;
      EXPECT_NE(what.find("not the 921600 baud asked"), std::string::npos) << what;
      EXPECT_NE(what.find("at 115200 baud"), std::string::npos) << what;  // the rate the line had
      std::printf("[ uart ] %s\n", what.c_str());
    }
  };
  {
    SerialHapticSink at_115200(config_, 16);  // leaves the line at 115,200, as the glove's other end
    at_115200.start();
    EXPECT_TRUE(at_115200.connected());
  }
  SerialHapticSink sink(fast, 16);
  expect_refused(sink);
  EXPECT_FALSE(sink.connected());
  SerialGloveSource source(fast, 16);
  expect_refused(source);
  EXPECT_EQ(source.state(), SourceState::kStopped);
  // Both rates a 16550A makes open as before.
  SerialConfig slow = config_;
  slow.baud = 9600;
  SerialGloveSource at_9600(slow, 16);
  at_9600.start();
  EXPECT_EQ(at_9600.state(), SourceState::kConnected);
  at_9600.stop();
  SerialHapticSink at_115200(config_, 16);
  at_115200.start();
  EXPECT_TRUE(at_115200.connected());
}

TEST_F(Uart, FlowControlAnEarlierProgramLeftOnDoesNotStallTheSink) {
  // A terminal program left CTS flow control (and XON/XOFF on input) on, and the glove does not
  // drive CTS (here: loopback with RTS low). The sink must send all the same.
  Line line(uart_path());
  ASSERT_TRUE(line.open()) << uart_path();
  ASSERT_TRUE(line.loop_back());
  ASSERT_TRUE(line.hold());
  ASSERT_TRUE(line.set_input_flow_control());
  SerialHapticSink sink(config_, 16);
  sink.start();
  ASSERT_TRUE(sink.connected());
  const termios after = line.settings();
  EXPECT_EQ(after.c_cflag & CRTSCTS, 0u);
  EXPECT_EQ(after.c_iflag & IXOFF, 0u);
  ASSERT_TRUE(sink.send(command(7)));
  Wire wire;
  EXPECT_TRUE(eventually([&] {
    wire.read(line);
    return wire.ends_with(7);
  })) << "the frame never left: "
      << line.unsent() << " bytes wait in the driver";
  sink.stop();
  wire.expect_whole_and_in_order();
}

TEST_F(Uart, TheSourceReadsEveryFrameThroughTheDriver) {
  // The glove's side of the line is the test's descriptor: what it writes loops back into the
  // UART's receiver (a 16-byte FIFO the driver empties on each interrupt), where the source
  // reads. Two hands of 250-byte positions frames, 1,000 of them in bursts of ten.
  SerialGloveSource source(config_, 4096);
  source.start();
  ASSERT_EQ(source.state(), SourceState::kConnected);
  Line line(uart_path());
  ASSERT_TRUE(line.open()) << uart_path();
  ASSERT_TRUE(line.loop_back());  // after the source's own settings of the same terminal
  constexpr std::uint32_t kFrames = 1000;
  std::vector<GloveSample> received;
  std::array<GloveSample, 64> batch{};
  const auto take = [&] {
    for (std::size_t n = source.poll(batch); n > 0; n = source.poll(batch)) {
      received.insert(received.end(), batch.begin(), batch.begin() + static_cast<std::ptrdiff_t>(n));
    }
  };
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    ASSERT_TRUE(line.write_sample(positions(static_cast<std::uint8_t>(i % 2), i / 2, i))) << "frame " << i;
    if (i % 10 == 9) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      take();
    }
  }
  ASSERT_TRUE(eventually([&] {
    take();
    return received.size() >= kFrames;
  })) << received.size()
      << " of " << kFrames << " samples";
  source.stop();
  const SourceCounters c = source.counters();
  std::printf("[ uart ] source: %llu samples, %llu CRC errors, %llu framing errors, %llu gaps\n",
              static_cast<unsigned long long>(c.samples), static_cast<unsigned long long>(c.crc_errors),
              static_cast<unsigned long long>(c.framing_errors), static_cast<unsigned long long>(c.sequence_gaps));
  EXPECT_EQ(c.crc_errors + c.framing_errors + c.sequence_gaps + c.overflows, 0u);
  ASSERT_EQ(received.size(), kFrames);
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    EXPECT_EQ(received[i].hand, i % 2) << i;
    EXPECT_EQ(received[i].sequence, i / 2) << i;
    EXPECT_EQ(received[i].joints[kJointPoints - 1][1], 1e-3f * i) << i;
  }
}

TEST_F(Uart, TheSinkQueuesAtMostAFrameBehindAStalledLineAndSendsTheNewestWhenItMoves) {
  // The glove stops reading for 300 ms while the loop sends a command every millisecond. The
  // driver would take about 4 KB (47 frames) behind which every later force waits; the sink
  // asks it (TIOCOUTQ) and writes only while at most a frame waits, holding the newest command
  // meanwhile. Released, the line carries the frames the driver held and then the newest.
  ASSERT_NO_FATAL_FAILURE(start_sink_on_held_line());
  Line& line = *line_;
  SerialHapticSink& sink = *sink_;
  constexpr std::uint32_t kCommands = 300;
  std::uint32_t accepted = 0;
  int most_unsent = 0;
  for (std::uint32_t t = 0; t < kCommands; ++t) {
    accepted += sink.send(command(t));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    most_unsent = std::max(most_unsent, line.unsent());
  }
  ASSERT_TRUE(eventually([&] { return sink.frames_written() + sink.superseded() + sink.dropped() + 1 >= accepted; }))
      << "the sink did not take every command";
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  most_unsent = std::max(most_unsent, line.unsent());
  const std::uint64_t written_while_held = sink.frames_written();

  Wire wire;
  ASSERT_NO_FATAL_FAILURE(release_until(wire, kCommands - 1));

  std::printf(
      "[ uart ] %u commands against a held line: at most %d bytes in the driver, %llu frames written while "
      "held, %zu on the wire, %llu superseded, %llu dropped\n",
      kCommands, most_unsent, static_cast<unsigned long long>(written_while_held), wire.ticks.size(),
      static_cast<unsigned long long>(sink.superseded()), static_cast<unsigned long long>(sink.dropped()));
  EXPECT_GT(most_unsent, 0) << "the line never held a byte: nothing here was tested";
  EXPECT_LE(most_unsent, static_cast<int>(2 * SerialHapticSink::kMaxBacklogBytes));
  EXPECT_LE(written_while_held, 2u);
  EXPECT_LE(wire.ticks.size(), 3u) << "a backlog of old forces reached the wire";
  EXPECT_EQ(wire.ticks.size(), sink.frames_written());
  EXPECT_EQ(sink.frames_written() + sink.superseded() + sink.dropped(), accepted);
  EXPECT_EQ(sink.dropped(), 0u);
  wire.expect_whole_and_in_order();
}

TEST_F(Uart, OnALineThatMovesInBurstsTheDriverNeverHoldsMoreThanTwoFrames) {
  // A glove slower than the loop: the line moves 1 ms in every 5 while a command comes every
  // millisecond, for a second. Counted in bytes and frames, not time, so that the guest's
  // emulated clock does not decide the result: the driver never holds more than two frames (the
  // one going out and the one behind it), every frame the sink wrote reaches the wire whole and
  // in order, and the last is the newest command. (When the test reads a frame says nothing
  // about the line: it reads once a millisecond.)
  ASSERT_NO_FATAL_FAILURE(start_sink_on_held_line());
  Line& line = *line_;
  SerialHapticSink& sink = *sink_;
  Wire wire;
  constexpr std::uint32_t kCommands = 1000;
  std::uint32_t accepted = 0;
  int most_unsent = 0;
  for (std::uint32_t t = 0; t < kCommands; ++t) {
    if (t % 5 == 4) {
      ASSERT_TRUE(line.release());
    } else if (t % 5 == 0) {
      ASSERT_TRUE(line.hold());
    }
    accepted += sink.send(command(t));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    most_unsent = std::max(most_unsent, line.unsent());
    wire.read(line);
  }
  ASSERT_NO_FATAL_FAILURE(release_until(wire, kCommands - 1));

  std::printf(
      "[ uart ] a line moving 1 ms in 5: %zu frames on the wire of %u commands, at most %d bytes in the driver, "
      "%llu superseded\n",
      wire.ticks.size(), accepted, most_unsent, static_cast<unsigned long long>(sink.superseded()));
  EXPECT_GT(most_unsent, 0) << "the line never held a byte: nothing here was tested";
  EXPECT_LE(most_unsent, static_cast<int>(2 * SerialHapticSink::kMaxBacklogBytes));
  EXPECT_EQ(wire.ticks.size(), sink.frames_written());
  for (std::size_t i = 0; i < wire.sequences.size(); ++i) {
    ASSERT_EQ(wire.sequences[i], i) << "a frame missing before " << i;
  }
  EXPECT_LT(wire.ticks.size(), static_cast<std::size_t>(accepted));
  EXPECT_EQ(sink.frames_written() + sink.superseded() + sink.dropped(), accepted);
  EXPECT_EQ(sink.dropped(), 0u);
  wire.expect_whole_and_in_order();
}

// ---- an FTDI USB-serial adapter, cabled to a UART ------------------------------------------------
// The backends on ttyUSB0 (qemu's emulated FTDI adapter, the kernel's ftdi_sio driver), the
// glove's end on ttyS2, the UART the adapter's cable goes to. Unplugging is the adapter's USB
// device deauthorised (the kernel unbinds it: the tty is hung up and its node removed, as when
// the cable is pulled) and plugging in is it authorised again (enumerated anew).

std::string env_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr ? value : "";
}

bool plug(bool in) {
  std::FILE* f = std::fopen((env_or_empty("GLOVE_ADAPTER_USB") + "/authorized").c_str(), "w");
  if (f == nullptr) return false;
  const bool written = std::fputs(in ? "1\n" : "0\n", f) >= 0;
  return std::fclose(f) == 0 && written;
}

class Adapter : public ::testing::Test {
 protected:
  void SetUp() override {
    if (env_or_empty("GLOVE_ADAPTER").empty()) GTEST_SKIP() << "no USB-serial adapter here (GLOVE_ADAPTER unset)";
    config_.device = env_or_empty("GLOVE_ADAPTER");
    config_.reconnect_interval_ms = 20.0;
    glove_ = std::make_unique<Line>(env_or_empty("GLOVE_ADAPTER_PEER"));
    ASSERT_TRUE(glove_->open()) << env_or_empty("GLOVE_ADAPTER_PEER");
    ASSERT_TRUE(glove_->make_raw());
  }
  void TearDown() override { plug(true); }

  // The glove sends samples n .. n + count - 1 of hand 0.
  void send_samples(std::uint32_t n, std::uint32_t count) {
    for (std::uint32_t i = n; i < n + count; ++i)
      ASSERT_TRUE(glove_->write_sample(positions(0, i, i))) << "frame " << i;
  }

  SerialConfig config_;
  std::unique_ptr<Line> glove_;  // the UART at the cable's other end
};

TEST_F(Adapter, TheSourceAndSinkComeBackAfterTheAdapterIsUnpluggedAndPluggedIn) {
  SerialGloveSource source(config_, 1024);
  SerialHapticSink sink(config_, 64);
  source.start();
  sink.start();
  ASSERT_EQ(source.state(), SourceState::kConnected);
  ASSERT_TRUE(sink.connected());
  std::array<GloveSample, 64> batch{};
  std::uint64_t received = 0;
  const auto take = [&] {
    for (std::size_t n = source.poll(batch); n > 0; n = source.poll(batch)) received += n;
    return received;
  };
  Line& glove_end = *glove_;
  Wire haptics;
  // Before: samples in, a haptic frame out.
  ASSERT_NO_FATAL_FAILURE(send_samples(0, 20));
  ASSERT_TRUE(eventually([&] { return take() == 20; })) << take() << " of 20 samples";
  const auto reaches_glove = [&](std::uint32_t tick) {
    return sink.send(command(tick)) && eventually([&] {
             haptics.read(glove_end);
             return haptics.ends_with(tick);
           });
  };
  ASSERT_TRUE(reaches_glove(1)) << "no haptic frame reached the glove";

  ASSERT_TRUE(plug(false)) << env_or_empty("GLOVE_ADAPTER_USB");
  EXPECT_TRUE(eventually([&] { return source.state() == SourceState::kDisconnected; })) << "the source did not notice";
  EXPECT_TRUE(eventually([&] { return !sink.connected(); })) << "the sink did not notice";
  EXPECT_EQ(source.counters().disconnects, 1u);
  sink.send(command(2));  // nowhere to go: dropped, never sent late
  EXPECT_TRUE(eventually([&] { return sink.dropped() >= 1; }));

  ASSERT_TRUE(plug(true));
  ASSERT_TRUE(eventually([&] { return source.state() == SourceState::kConnected && sink.connected(); },
                         std::chrono::seconds(20)))
      << "the adapter came back but the backends did not reconnect";
  EXPECT_EQ(source.counters().reconnects, 1u);
  ASSERT_NO_FATAL_FAILURE(send_samples(20, 20));
  EXPECT_TRUE(eventually([&] { return take() == 40; })) << take() << " of 40 samples";
  EXPECT_TRUE(reaches_glove(3)) << "no haptic frame reached the glove after the reconnect";
  source.stop();
  sink.stop();
  std::printf(
      "[ adapter ] unplugged and plugged in: %llu samples, %llu disconnect, %llu reconnect; sink %llu "
      "frames, %llu dropped\n",
      static_cast<unsigned long long>(received), static_cast<unsigned long long>(source.counters().disconnects),
      static_cast<unsigned long long>(source.counters().reconnects),
      static_cast<unsigned long long>(sink.frames_written()), static_cast<unsigned long long>(sink.dropped()));
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.crc_errors + c.framing_errors, 0u);
  EXPECT_EQ(haptics.ticks, (std::vector<std::uint32_t>{1, 3}));
  haptics.expect_whole_and_in_order();
}

}  // namespace
}  // namespace sculpt::hal
