#pragma once
// What the viewer's process tests share: a private X server (Xvfb) for the window, a bundled
// scene copied into a temporary folder with its outputs there and its own LCM port, and the
// viewer's status lines read back from its output.

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "hil/child_process.hpp"
#include "support/bundled_scene.hpp"
#include "sculpt/deform/point_model.hpp"

namespace sculpt::test {

namespace fs = std::filesystem;

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The lines of `text` that start with `prefix`.
inline std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
  }
  return lines;
}

/// Polls `path` until a line starting with `prefix` is in it, for at most `limit`.
inline bool wait_for_line(const fs::path& path, const std::string& prefix, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (!lines_starting(read_text(path), prefix).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

/// The same points, float-equal, in the same order (what "the viewer's copy is the station's
/// model" means; normals and faces follow the points).
inline bool same_points(const deform::PointModel& a, const deform::PointModel& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const deform::Vec3 p = a.position(i), q = b.position(i);
    if (p.x != q.x || p.y != q.y || p.z != q.z) return false;
  }
  return true;
}

/// An Xvfb of the test's own, and DISPLAY pointing at it for every child started after it.
class VirtualDisplay {
 public:
  explicit VirtualDisplay(const fs::path& log) {
    if (std::system("command -v Xvfb > /dev/null 2>&1") != 0) return;
    // A display number of its own: not one another server holds (its lock file), nor one an
    // earlier test of this process used.
    static int used = 0;
    for (number_ = 60 + (getpid() % 100) * 5 + used++ % 5; fs::exists("/tmp/.X" + std::to_string(number_) + "-lock");
         number_ += 500) {
    }
    const std::string name = std::string(":").append(std::to_string(number_));
    server_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{"Xvfb", name, "-screen", "0", "1024x768x24", "-nolisten", "tcp"}, log.string());
    const fs::path socket = "/tmp/.X11-unix/X" + std::to_string(number_);
    for (int i = 0; i < 100 && !fs::exists(socket); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!fs::exists(socket)) return;
    setenv("DISPLAY", name.c_str(), 1);
    ready_ = true;
  }
  ~VirtualDisplay() {
    if (server_) {
      server_->signal(SIGTERM);  // Xvfb removes its lock file and socket on SIGTERM, not on SIGKILL
      server_->wait(std::chrono::seconds(10));
    }
  }
  VirtualDisplay(const VirtualDisplay&) = delete;
  VirtualDisplay& operator=(const VirtualDisplay&) = delete;
  bool ready() const { return ready_; }

 private:
  int number_ = 0;
  std::unique_ptr<ChildProcess> server_;
  bool ready_ = false;
};

/// A temporary folder (kept when the test fails) and a bundled scene rewritten into it.
class SessionFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sculpt-view-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  /// A private multicast port per test process and `offset`, so parallel runs do not hear each other.
  static std::string private_url(int offset) {
    return std::string("udpm://239.255.76.67:")
        .append(std::to_string(8300 + offset + getpid() % 200 * 4))
        .append("?ttl=0");
  }

  /// scenes/<name>.toml copied into the folder (test::copy_bundled_scene).
  fs::path scene(const std::string& name, const std::string& extra,
                 const std::vector<std::pair<std::string, std::string>>& edits = {}) const {
    return copy_bundled_scene(dir_, name, extra, edits);
  }

  /// The one-finger press with a dead band below one glove sample's step, so that the press
  /// is a frame per sample (about fifteen in contact) rather than the default's two. With
  /// `log_every_tick`, its log keeps every tick's record, as the live channel carries them.
  fs::path press_scene(const std::string& extra, bool log_every_tick = false) const {
    std::vector<std::pair<std::string, std::string>> edits = {{"mode = \"push\"", "mode = \"push\"\ndelta_s = 0.004"}};
    if (log_every_tick) edits.emplace_back("[output]", "[output]\ntick_interval_ms = 0");
    return scene("sphere-press", extra, edits);
  }

  /// Runs the station on `scene` for `seconds`, quietly; its exit code.
  int run_station(const fs::path& scene, double seconds, const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> args = {SCULPT_BINARY,           "run",    scene.string(), "--duration",
                                     std::to_string(seconds), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    ChildProcess run(args, (dir_ / "run.txt").string());
    return run.wait();
  }

  fs::path dir_;
};

/// Besides the folder, an X server for the viewer's window; the test is skipped without Xvfb.
class ViewSession : public SessionFolder {
 protected:
  void SetUp() override {
    SessionFolder::SetUp();
    display_ = std::make_unique<VirtualDisplay>(dir_ / "xvfb.txt");
    if (!display_->ready()) GTEST_SKIP() << "no Xvfb to open the viewer's window on (apt install xvfb)";
  }
  void TearDown() override {
    display_.reset();
    SessionFolder::TearDown();
  }

  /// Sends `keys` (xdotool key names) to the viewer's window, focusing it first: without a
  /// window manager the keyboard goes wherever the input focus was set.
  static bool send_keys(const std::string& keys) {
    const std::string command =
        "timeout 20 xdotool search --sync --onlyvisible --name 'sculpt view' windowfocus --sync key " + keys +
        " > /dev/null 2>&1";
    return std::system(command.c_str()) == 0;
  }

  /// Runs xdotool's mouse `actions` on the viewer's window, focused first; %1 names the window
  /// (e.g. "mousemove --window %1 200 150 mousedown 1 ... mouseup 1 click 4").
  static bool send_mouse(const std::string& actions) {
    const std::string command =
        "timeout 20 xdotool search --sync --onlyvisible --name 'sculpt view' windowfocus --sync " + actions +
        " > /dev/null 2>&1";
    return std::system(command.c_str()) == 0;
  }

  std::unique_ptr<VirtualDisplay> display_;
};

}  // namespace sculpt::test
