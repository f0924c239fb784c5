// Hardware in the loop: `sculpt glove-sim` and `sculpt run` as separate processes, joined by
// the real transports. Over serial, two pseudo-terminal pairs with a relay in this test
// between them, which injects garbage, truncated frames and bad checksums and unplugs the
// station's port for a while; over LCM, multicast on loopback.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../../hal/src/cobs.hpp"
#include "child_process.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/hal/frame_codec.hpp"

namespace sculpt {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kSculpt = SCULPT_BINARY;
const std::string kScene = std::string(SCULPT_SOURCE_DIR) + "/scenes/sphere-press.toml";

using Process = test::ChildProcess;

struct Pty {
  int master = -1;
  std::string slave_path;
  int slave = -1;  // kept open so the slave side stays valid between the children's opens
  bool open_pair() {
    char name[128];
    if (openpty(&master, &slave, name, nullptr, nullptr) != 0) return false;
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

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

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

// A frame whose payload was changed after its checksum was computed: whole, but corrupt.
std::vector<std::uint8_t> bad_crc_frame() {
  hal::GloveSample s;
  for (auto& j : s.joints) j = {0.25f, 0.5f, 3.0f};  // far from the model: harmless if accepted
  std::uint8_t encoded[hal::kMaxFrameBytes];
  const std::size_t n = hal::encode_sample_frame(s, encoded);
  std::uint8_t body[hal::kMaxFrameBytes];
  const std::ptrdiff_t m = hal::cobs_decode({encoded, n - 1}, body);
  body[40] ^= 0x10;
  std::vector<std::uint8_t> out(hal::kMaxFrameBytes);
  const std::size_t k = hal::cobs_encode({body, static_cast<std::size_t>(m)}, out);
  out.resize(k);
  out.push_back(0);
  return out;
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
  Process station(
      {kSculpt, "run", kScene, "--serial", link.string(), "--duration", "6", "--json", json, "--out", out, "--quiet"},
      (dir / "run.log").string());
  ASSERT_TRUE(station.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  Process glove({kSculpt, "glove-sim", kScene, "--serial", glove_side.slave_path}, (dir / "glove.log").string());
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

  EXPECT_EQ(glove.wait(std::chrono::seconds(20)), 0) << read_file((dir / "glove.log").string());
  EXPECT_EQ(station.wait(std::chrono::seconds(20)), 0) << read_file((dir / "run.log").string());
  done.store(true);
  relay.join();
  glove_side.close_pair();
  station_side.close_pair();

  const nlohmann::json r = nlohmann::json::parse(read_file(json));
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
  const fs::path dir = fs::temp_directory_path() / ("sculpt-hil-lcm-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string url = "udpm://239.255.76.67:" + std::to_string(7700 + getpid() % 200) + "?ttl=0";
  const std::string json = (dir / "run.json").string();
  Process station({kSculpt, "run", kScene, "--lcm", url, "--duration", "5", "--json", json, "--quiet"},
                  (dir / "run.log").string());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // a late subscriber misses messages
  Process glove({kSculpt, "glove-sim", kScene, "--lcm", url}, (dir / "glove.log").string());
  EXPECT_EQ(glove.wait(std::chrono::seconds(20)), 0) << read_file((dir / "glove.log").string());
  const int code = station.wait(std::chrono::seconds(20));
  const std::string log = read_file((dir / "run.log").string());
  if (code != 0 && log.find("lcm") != std::string::npos && log.find("cannot") != std::string::npos) {
    GTEST_SKIP() << "multicast LCM is not available here: " << log;
  }
  ASSERT_EQ(code, 0) << log;
  const nlohmann::json r = nlohmann::json::parse(read_file(json));
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
  Process station({kSculpt, "run", kScene, "--json", json, "--out", out, "--quiet"}, (dir / "run.log").string());
  ASSERT_TRUE(station.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  station.signal(SIGTERM);
  EXPECT_EQ(station.wait(std::chrono::seconds(20)), 0) << "not a clean exit: " << read_file((dir / "run.log").string());
  const nlohmann::json r = nlohmann::json::parse(read_file(json));
  EXPECT_GT(r["ticks"].get<int>(), 500);
  EXPECT_EQ(deform::read_model(out).size(), 3203u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sculpt
