// Hardware in the loop: `sculpt glove-sim` and `sculpt run` as separate processes, joined by
// the real transports. Over serial, two pseudo-terminal pairs with a relay in this test
// between them, which injects garbage, truncated frames and bad checksums and unplugs the
// station's port for a while; over LCM, multicast on loopback. The station's haptic frames
// over serial are captured by this test on a pseudo-terminal and checked as a glove would feel them.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "support/bundled_scene.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/hal/frame_codec.hpp"
#include "support/file_contents.hpp"

namespace sculpt {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kSculpt = SCULPT_BINARY;

using test::file_contents;

// A copy of the bundled one-finger press for a test, outputs into `dir` and `extra` appended.
// Built without LCM the station has no event log: a scene asking for one is refused (tested by
// the command-line script), so these tests run the same scene without its log line.
fs::path scene_copy(const fs::path& dir, const std::string& extra) {
#if SCULPT_TEST_WITH_LCM
  return test::copy_bundled_scene(dir, "sphere-press", extra);
#else
  return test::copy_bundled_scene(dir, "sphere-press", extra, {{"log = \"../out/sphere-press.lcmlog\"\n", ""}});
#endif
}

using Process = test::ChildProcess;

struct Pty {
  int master = -1;
  std::string slave_path;
  int slave = -1;  // kept open so the slave side stays valid between the children's opens
  bool open_pair() {
    char name[128];
    // Raw from the start, as a real serial line is: a pseudo-terminal is born in cooked mode
    // until its reader sets raw, and bytes written before the station opens it (it may still be
    // loading its model, slowly under a sanitizer) go through the line discipline, whose
    // kill and erase characters delete random garbage and the frames before it.
    termios raw{};
    cfmakeraw(&raw);
    if (openpty(&master, &slave, name, &raw, nullptr) != 0) return false;
    slave_path = name;
    fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
    // Not inherited by the children: otherwise closing the master here would not unplug the line.
    fcntl(master, F_SETFD, FD_CLOEXEC);
    fcntl(slave, F_SETFD, FD_CLOEXEC);
    return true;
  }
  void close_pair() {
    if (master >= 0) close(master);
    if (slave >= 0) close(slave);
    master = slave = -1;
  }
};

void write_all(int fd, const std::uint8_t* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = write(fd, data, n);
    if (w > 0) {
      data += w;
      n -= static_cast<std::size_t>(w);
    } else if (w < 0 && errno != EAGAIN && errno != EINTR) {
      return;
    } else {
      pollfd p{fd, POLLOUT, 0};
      poll(&p, 1, 10);
    }
  }
}

// A frame whose payload was changed after its checksum was computed: whole, but corrupt. In
// COBS each code byte says how far the next one is and every other byte is payload, so turning
// a payload byte into another non-zero value keeps the framing and breaks only the CRC.
std::vector<std::uint8_t> bad_crc_frame() {
  hal::GloveSample s;
  for (auto& j : s.joints) j = {0.25f, 0.5f, 3.0f};  // far from the model: harmless if accepted
  std::vector<std::uint8_t> frame(hal::kMaxFrameBytes);
  frame.resize(hal::encode_sample_frame(s, frame));
  std::vector<bool> code(frame.size(), false);
  for (std::size_t at = 0; at + 1 < frame.size(); at += frame[at]) code[at] = true;
  std::size_t at = 41;  // in the joints: a body byte the decoder reads
  while (code[at]) ++at;
  frame[at] = static_cast<std::uint8_t>((frame[at] ^ 0x10) != 0 ? frame[at] ^ 0x10 : frame[at] ^ 0x20);
  return frame;
}

TEST(HardwareInTheLoop, SerialThroughAFaultyLineKeepsTheStationRunning) {
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-" + std::to_string(getpid()));
  fs::create_directories(dir);
  Pty glove_side, station_side;
  ASSERT_TRUE(glove_side.open_pair());
  ASSERT_TRUE(station_side.open_pair());
  const fs::path link = dir / "glove";
  fs::create_symlink(station_side.slave_path, link);

  const std::string json = (dir / "run.json").string(), out = (dir / "out.ply").string();
  const std::string scene = scene_copy(dir, "").string();
  Process station(
      {kSculpt, "run", scene, "--serial", link.string(), "--duration", "6", "--json", json, "--out", out, "--quiet"},
      (dir / "run.log").string());
  ASSERT_TRUE(station.started());
  // The line's faults are injected on a schedule from here: with LCM, only once the station has
  // opened its port (its log begins after its glove started), or a slow start (a sanitizer build
  // beside a busy test) opened and flushed the port after the faults and counted none of them.
  // The minimal build keeps no log; its runs are not slowed by a sanitizer.
#if SCULPT_HAS_LCM
  const fs::path session_log = dir / "sphere-press.lcmlog";
  const auto give_up = Clock::now() + std::chrono::seconds(60);
  while (!(fs::exists(session_log) && fs::file_size(session_log) > 0) && Clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(fs::exists(session_log) && fs::file_size(session_log) > 0)
      << "the station did not start in 60 s: " << file_contents((dir / "run.log").string());
#else
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
#endif
  Process glove({kSculpt, "glove-sim", scene, "--serial", glove_side.slave_path}, (dir / "glove.log").string());
  ASSERT_TRUE(glove.started());

  // The relay: copy the glove's bytes to the station's line, and break the line on schedule.
  std::atomic<bool> done{false};
  int injected_garbage = 0, injected_truncated = 0, injected_bad_crc = 0, unplugs = 0;
  std::thread relay([&] {
    const auto start = Clock::now();
    std::mt19937 rng(7);
    bool garbage = false, truncated = false, bad = false, unplugged = false, replugged = false;
    std::uint8_t buffer[4096];
    while (!done.load()) {
      pollfd p{glove_side.master, POLLIN, 0};
      poll(&p, 1, 5);
      const ssize_t n = read(glove_side.master, buffer, sizeof buffer);
      const double t = std::chrono::duration<double>(Clock::now() - start).count();
      const bool line_up = !unplugged || replugged;
      if (n > 0 && line_up) write_all(station_side.master, buffer, static_cast<std::size_t>(n));
      if (!garbage && t > 0.4) {
        std::vector<std::uint8_t> junk(300);
        for (auto& b : junk) b = static_cast<std::uint8_t>(1 + rng() % 255);
        junk.push_back(0);
        write_all(station_side.master, junk.data(), junk.size());
        garbage = true;
        ++injected_garbage;
      }
      if (!truncated && t > 0.6) {
        hal::GloveSample s;
        std::uint8_t frame[hal::kMaxFrameBytes];
        const std::size_t k = hal::encode_sample_frame(s, frame);
        frame[k / 2] = 0;  // cut in the middle: the rest of the frame is lost
        write_all(station_side.master, frame, k / 2 + 1);
        truncated = true;
        ++injected_truncated;
      }
      if (!bad && t > 0.8) {
        for (int i = 0; i < 3; ++i) {
          const std::vector<std::uint8_t> f = bad_crc_frame();
          write_all(station_side.master, f.data(), f.size());
          ++injected_bad_crc;
        }
        bad = true;
      }
      if (!unplugged && t > 1.6) {  // the port disappears...
        station_side.close_pair();
        unplugged = true;
        ++unplugs;
      }
      if (unplugged && !replugged && t > 2.0) {  // ...and comes back, at the same path
        station_side.open_pair();
        const fs::path tmp = dir / "glove.new";
        fs::create_symlink(station_side.slave_path, tmp);
        fs::rename(tmp, link);
        replugged = true;
      }
    }
  });

  EXPECT_EQ(glove.wait(std::chrono::seconds(20)), 0) << file_contents((dir / "glove.log").string());
  EXPECT_EQ(station.wait(std::chrono::seconds(20)), 0) << file_contents((dir / "run.log").string());
  done.store(true);
  relay.join();
  glove_side.close_pair();
  station_side.close_pair();

  const nlohmann::json r = nlohmann::json::parse(file_contents(json));
  std::printf("[ hil ] serial: %s\n", r.dump().c_str());
  // The loop never stopped: about 6 s at 1 kHz (only gross failure is asserted here).
  EXPECT_GT(r["ticks"].get<double>(), 3000.0);
  // Every fault was seen, counted by kind, and the samples kept coming afterwards.
  const auto& faults = r["faults"];
  EXPECT_GE(faults["crc_errors"].get<int>(), injected_bad_crc);
  EXPECT_GE(faults["framing_errors"].get<int>(), injected_garbage + injected_truncated);
  EXPECT_GE(faults["disconnects"].get<int>(), unplugs);
  EXPECT_GE(faults["reconnects"].get<int>(), unplugs);
  EXPECT_GT(faults["sequence_gaps"].get<int>(), 0);  // what the unplugged line swallowed
  EXPECT_GT(r["collisions"].get<int>(), 0);
  // The model deformed where the trajectory pressed: the top of the sphere went in.
  const deform::PointModel model = deform::read_model(out);
  double top = -1.0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (std::abs(model.x[i]) < 0.05f && std::abs(model.y[i]) < 0.05f && model.z[i] > 0.0f)
      top = std::max(top, double(model.z[i]));
  }
  EXPECT_LT(top, 0.99);
  fs::remove_all(dir);
}

TEST(HardwareInTheLoop, LcmMulticastOnLoopback) {
#if !SCULPT_TEST_WITH_LCM
  GTEST_SKIP() << "built without LCM (-DSCULPT_WITH_LCM=OFF)";
#endif
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-lcm-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string url = "udpm://239.255.76.67:" + std::to_string(7700 + getpid() % 200) + "?ttl=0";
  const std::string json = (dir / "run.json").string();
  const std::string scene = scene_copy(dir, "").string();
  Process station({kSculpt, "run", scene, "--lcm", url, "--duration", "5", "--json", json, "--quiet"},
                  (dir / "run.log").string());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // a late subscriber misses messages
  Process glove({kSculpt, "glove-sim", scene, "--lcm", url}, (dir / "glove.log").string());
  EXPECT_EQ(glove.wait(std::chrono::seconds(20)), 0) << file_contents((dir / "glove.log").string());
  const int code = station.wait(std::chrono::seconds(20));
  const std::string log = file_contents((dir / "run.log").string());
  if (code != 0 && log.find("lcm") != std::string::npos && log.find("cannot") != std::string::npos) {
    GTEST_SKIP() << "multicast LCM is not available here: " << log;
  }
  ASSERT_EQ(code, 0) << log;
  const nlohmann::json r = nlohmann::json::parse(file_contents(json));
  std::printf("[ hil ] lcm: %s\n", r.dump().c_str());
  EXPECT_GT(r["glove_samples"].get<int>(), 100);
  EXPECT_GT(r["collisions"].get<int>(), 0);
  fs::remove_all(dir);
}

// SIGTERM mid-run: the station ends cleanly, writing its model and summary.
TEST(HardwareInTheLoop, SigtermEndsTheRunCleanly) {
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-term-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string json = (dir / "run.json").string(), out = (dir / "out.ply").string();
  Process station({kSculpt, "run", scene_copy(dir, "").string(), "--json", json, "--out", out, "--quiet"},
                  (dir / "run.log").string());
  ASSERT_TRUE(station.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  station.signal(SIGTERM);
  EXPECT_EQ(station.wait(std::chrono::seconds(20)), 0)
      << "not a clean exit: " << file_contents((dir / "run.log").string());
  const nlohmann::json r = nlohmann::json::parse(file_contents(json));
  EXPECT_GT(r["ticks"].get<int>(), 500);
  EXPECT_EQ(deform::read_model(out).size(), 3203u);
  fs::remove_all(dir);
}

// What a glove on the station's serial haptic line received, as this test decoded it.
struct HapticCapture {
  struct Frame {
    std::uint32_t sequence, tick;
    std::uint64_t device_time_us;  // the sender's clock when it wrote the frame
    double force;                  // the index finger's magnitude, newtons
    bool in_contact;
  };
  int exit_code = -1;
  std::string run_log;
  nlohmann::json haptic;  // the run summary's account of its sink
  std::vector<Frame> frames;
  hal::DecoderCounters decoder;
  std::uint64_t samples_seen = 0;
  std::uint64_t bytes = 0;
};

// Runs the one-finger press (sphere-press, 3.5 s) as its own process with a serial haptic sink
// on a pseudo-terminal whose master this test reads, at most `line_bytes_per_s` (0: as fast as
// the pty gives them; a pty has no baud rate of its own), decoding with hal's frame codec.
HapticCapture capture_serial_haptics(const fs::path& dir, double line_bytes_per_s) {
  HapticCapture c;
  c.frames.reserve(20000);
  Pty line;
  if (!line.open_pair()) {
    c.run_log = "openpty failed";
    return c;
  }
  const fs::path scene = scene_copy(dir,
                                    "[haptic]\nsink = \"serial\"\nmax_force = 4.0\nmax_force_rate = 200.0\n"
                                    "[haptic.serial]\ndevice = \"" +
                                        line.slave_path + "\"\n");
  hal::FrameDecoder decoder;
  std::atomic<bool> done{false};
  std::thread reader([&] {
    std::uint8_t buffer[4096];
    auto on_frame = [&](const hal::DecodedFrame& f) {
      if (f.type != hal::DecodedFrame::Type::kHaptic) {
        ++c.samples_seen;
        return;
      }
      const auto& v = f.haptic.force[1];
      c.frames.push_back({f.sequence, f.haptic.tick, f.device_time_us,
                          std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]),
                          (f.haptic.active_mask & 0b10) != 0});
    };
    // A slower line, as a token bucket: it carries line_bytes_per_s, and an idle line saves up
    // no more than two frames' worth (a real line's idle time is lost, not banked).
    double credit = 0.0;
    auto last = Clock::now();
    for (bool last_pass = false;;) {
      std::size_t room = sizeof buffer;
      if (line_bytes_per_s > 0.0) {
        const auto now = Clock::now();
        credit = std::min(credit + line_bytes_per_s * std::chrono::duration<double>(now - last).count(), 2.0 * 87.0);
        last = now;
        if (credit < 1.0) {
          std::this_thread::sleep_for(std::chrono::microseconds(500));
          continue;
        }
        room = std::min(room, static_cast<std::size_t>(credit));
      }
      pollfd p{line.master, POLLIN, 0};
      poll(&p, 1, 20);
      const ssize_t n = read(line.master, buffer, room);
      if (n > 0) {
        c.bytes += static_cast<std::uint64_t>(n);
        credit -= static_cast<double>(n);
        decoder.feed({buffer, static_cast<std::size_t>(n)}, on_frame);
      } else if (last_pass) {
        break;  // the station has exited and the line is drained
      } else if (done.load()) {
        last_pass = true;
      }
    }
  });
  {
    Process station({kSculpt, "run", scene.string(), "--duration", "3.5", "--quiet"}, (dir / "run.log").string());
    if (station.started()) c.exit_code = station.wait(std::chrono::seconds(60));
  }
  done.store(true);
  reader.join();
  line.close_pair();
  c.decoder = decoder.counters();
  c.run_log = file_contents((dir / "run.log").string());
  if (c.exit_code == 0) c.haptic = nlohmann::json::parse(file_contents((dir / "sphere-press.json").string()))["haptic"];
  return c;
}

// What a glove must feel from the press, however fast the line: every frame the station wrote
// arrived whole (its count in the summary, the sink's own sequence numbers without a gap);
// nothing above the 4 N clamp; force rising no faster than max_force_rate allows over the loop
// ticks between two received frames, plus one tick's rise; ticks strictly increasing (a slow
// line skips superseded commands, never reorders); commands all through the contact, never
// silent for 100 ms; and zero force once the finger lets go.
struct Contact {
  std::size_t frames = 0;   // commands received with the finger in contact
  std::uint32_t ticks = 0;  // loop ticks from the first of them to the last
  double seconds = 0.0;     // the same stretch by the sender's clock
};
Contact expect_felt_as_a_glove(const HapticCapture& c, const char* line) {
  constexpr double kMaxForce = 4.0, kMaxForceRate = 200.0, kRateHz = 1000.0;
  EXPECT_EQ(c.decoder.crc_errors, 0u);
  EXPECT_EQ(c.decoder.framing_errors, 0u);
  EXPECT_EQ(c.samples_seen, 0u) << "the station only writes haptic frames";
  if (c.frames.empty()) {
    ADD_FAILURE() << "no haptic frame came over the line";
    return {};
  }
  EXPECT_EQ(c.haptic["sink"], "serial");
  EXPECT_EQ(c.haptic["delivered"].get<std::size_t>(), c.frames.size()) << "a pty loses nothing";
  EXPECT_EQ(c.haptic["dropped"].get<std::size_t>(), 0u);
  EXPECT_EQ(c.frames.front().sequence, 0u);
  double peak = 0.0, steepest = 0.0;  // steepest rise between received frames, N per loop second
  std::size_t in_contact = 0, first_contact = c.frames.size(), last_contact = 0;
  for (std::size_t i = 0; i < c.frames.size(); ++i) {
    const HapticCapture::Frame& f = c.frames[i];
    peak = std::max(peak, f.force);
    if (f.in_contact) {
      ++in_contact;
      first_contact = std::min(first_contact, i);
      last_contact = i;
    }
    if (i == 0) continue;
    const HapticCapture::Frame& e = c.frames[i - 1];
    // The sink numbers its frames from 0 as it writes them: a gap is a frame lost on the line.
    EXPECT_EQ(f.sequence, e.sequence + 1) << "frame " << i;
    if (f.tick <= e.tick) {
      ADD_FAILURE() << "frame " << i << ": tick " << f.tick << " after " << e.tick;
      return {};
    }
    // Falling force and release are never delayed; a rise is bounded by the ticks it had.
    const double ticks = static_cast<double>(f.tick - e.tick);
    steepest = std::max(steepest, (f.force - e.force) * kRateHz / ticks);
    EXPECT_LE(f.force - e.force, kMaxForceRate * (ticks + 1.0) / kRateHz + 1e-5)
        << "frame " << i << ": ticks " << e.tick << " -> " << f.tick;
  }
  EXPECT_LE(peak, kMaxForce + 1e-6);
  EXPECT_GT(peak, 1.0) << "the press should be felt";
  if (in_contact == 0) {
    ADD_FAILURE() << "no command with the finger in contact";
    return {};
  }
  std::uint32_t longest_gap = 0;
  for (std::size_t i = first_contact + 1; i <= last_contact; ++i) {
    EXPECT_TRUE(c.frames[i].in_contact) << "frame " << i << ": contact is one stretch in this press";
    longest_gap = std::max(longest_gap, c.frames[i].tick - c.frames[i - 1].tick);
  }
  Contact contact;
  contact.frames = in_contact;
  contact.ticks = c.frames[last_contact].tick - c.frames[first_contact].tick + 1;
  contact.seconds =
      1e-6 * static_cast<double>(c.frames[last_contact].device_time_us - c.frames[first_contact].device_time_us);
  // By the sender's clock, not in ticks: a loaded machine's loop misses periods.
  EXPECT_GT(contact.seconds, 1.0) << "the press holds the finger in the surface for about 1.4 s";
  EXPECT_LE(longest_gap, 100u) << "a silence of " << longest_gap << " ticks while in contact";
  // Release: the first command after the contact, and the last one, send no force.
  EXPECT_LT(last_contact + 1, c.frames.size()) << "no command after the finger let go";
  if (last_contact + 1 < c.frames.size()) {
    EXPECT_EQ(c.frames[last_contact + 1].force, 0.0);
  }
  EXPECT_FALSE(c.frames.back().in_contact);
  EXPECT_EQ(c.frames.back().force, 0.0);
  // The summary's own account of the contact: the sink took a command every tick the hand was
  // in it (a slow line supersedes after that), and the line carried at most those.
  const nlohmann::json& touched = c.haptic["in_contact"];
  if (touched.size() != 1u) {
    ADD_FAILURE() << "one hand touched: " << touched.dump();
  } else {
    EXPECT_EQ(touched[0]["hand"].get<int>(), 0);
    const auto summary_ticks = touched[0]["ticks"].get<std::uint64_t>();
    EXPECT_EQ(touched[0]["commands"].get<std::uint64_t>(), summary_ticks);
    EXPECT_GE(summary_ticks, contact.ticks) << "the line saw contact over more ticks than the station counted";
    EXPECT_LE(in_contact, summary_ticks);
    EXPECT_GT(touched[0]["rate_hz"].get<double>(), 0.0);
    // And what reached the line while in contact is what the glove decoded with a contact.
    EXPECT_EQ(touched[0]["delivered"].get<std::uint64_t>(), in_contact);
    EXPECT_GT(touched[0]["delivered_rate_hz"].get<double>(), 0.0);
  }
  std::printf(
      "[ hil ] serial haptic, %s: %zu frames (%.1f bytes each), %zu in contact over %u ticks (%.0f Hz by "
      "the sender's clock), %llu superseded, longest gap %u ticks, peak %.3f N, steepest rise %.1f N/s; "
      "summary %s\n",
      line, c.frames.size(), static_cast<double>(c.bytes) / static_cast<double>(c.frames.size()), in_contact,
      contact.ticks, contact.seconds > 0.0 ? static_cast<double>(in_contact - 1) / contact.seconds : 0.0,
      static_cast<unsigned long long>(c.haptic["superseded"].get<std::uint64_t>()), longest_gap, peak, steepest,
      c.haptic.dump().c_str());
  return contact;
}

// Issue 8's serial must-show, the station in its own process: as fast as the line goes, the
// glove gets a command nearly every loop tick of the contact (half is the bar: a loaded machine
// may stall the writer thread).
TEST(HardwareInTheLoop, SerialHapticFramesFromAnotherProcessAreClampedSlewLimitedHeldAndReleased) {
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-haptic-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const HapticCapture c = capture_serial_haptics(dir, 0.0);
  ASSERT_EQ(c.exit_code, 0) << c.run_log;
  const Contact contact = expect_felt_as_a_glove(c, "a fast line");
  EXPECT_GE(2 * contact.frames, contact.ticks) << "fewer than half the loop's ticks reached the glove";
  fs::remove_all(dir);
}

// A line slower than the loop, as 460,800 baud would be (46,080 bytes/s, about 530 frames/s
// against 1,000 commands/s): the sink carries the newest command of each tick it gets to and
// counts the rest as superseded, so the glove still feels a bounded, slew-limited force that
// is released, at the rate the line allows. (Between the sink and the test the pty's kernel
// buffer holds about 20 KB, a UART driver's about 4 KB: on a full line every frame is late by
// that much, in order.)
TEST(HardwareInTheLoop, SerialHapticsOverALineSlowerThanTheLoopCarryTheNewestCommandsAtItsRate) {
  constexpr double kLineBytesPerSecond = 460800.0 / 10.0;  // 8N1: ten bits a byte
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-haptic-slow-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const HapticCapture c = capture_serial_haptics(dir, kLineBytesPerSecond);
  ASSERT_EQ(c.exit_code, 0) << c.run_log;
  const Contact contact = expect_felt_as_a_glove(c, "460,800 baud");
  ASSERT_GT(contact.seconds, 0.0);
  // The line's frame rate against the loop's: where the loop outran the line (always, unless a
  // sanitizer slowed the loop below 530 Hz), the commands it could not carry were superseded,
  // not queued, and the glove got fewer than one a tick.
  const double line_hz = kLineBytesPerSecond * static_cast<double>(c.frames.size()) / static_cast<double>(c.bytes);
  const double loop_hz = static_cast<double>(contact.ticks) / contact.seconds;
  if (loop_hz > 1.2 * line_hz) {
    EXPECT_GT(c.haptic["superseded"].get<std::uint64_t>(), 0u) << "the line cannot carry every tick";
    EXPECT_LT(contact.frames, contact.ticks);
  } else {
    std::printf("[ hil ] the loop ran at %.0f Hz, not faster than the line's %.0f frames/s: nothing to supersede\n",
                loop_hz, line_hz);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sculpt
