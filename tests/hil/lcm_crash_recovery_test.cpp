// Recovery from a crash, in separate processes: a station writing its own durable log is
// killed with SIGKILL at random moments, and `sculpt replay` of what is left must be the
// completed session replayed up to the same last whole frame, byte for byte. Which frames are
// whole in a cut log is found here, from the log's own events, not from replay's report.
#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/records.hpp"
#include "support/file_contents.hpp"

namespace sculpt {
namespace {

namespace fs = std::filesystem;

using test::file_contents;

int sculpt(const std::vector<std::string>& args, const fs::path& output) {
  std::vector<std::string> argv = {SCULPT_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  test::ChildProcess child(argv, output.string());
  return child.wait();
}

std::uintmax_t size_of(const fs::path& p) {
  std::error_code error;
  const std::uintmax_t size = fs::file_size(p, error);
  return error ? 0 : size;
}

// The frames of a log whose every event (as many as their frame_size) is in it.
struct WholeFrames {
  std::int64_t last_frame = -1;
  std::size_t events = 0;
};

WholeFrames whole_frames_in(const fs::path& path) {
  std::map<std::int64_t, std::pair<std::size_t, std::size_t>> frames;  // id -> (events, frame_size)
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    if (r != logging::EventLogReader::Result::kEvent || event.channel != logging::kCollisionChannel) continue;
    sculpt_lcm::collision_event_t message;
    std::string error;
    if (!logging::decode(event, message, error)) continue;
    auto& f = frames[message.frame_id];
    ++f.first;
    f.second = static_cast<std::size_t>(message.frame_size);
  }
  WholeFrames w;
  for (const auto& [id, f] : frames) {
    if (f.first != f.second) continue;
    w.last_frame = id;
    w.events += f.first;
  }
  return w;
}

// A folder of the test's own, kept when it fails so the logs can be looked at.
class CrashRecovery : public ::testing::Test {
 protected:
  CrashRecovery()
      : dir_(fs::temp_directory_path() / ("sculpt-crash-" + std::to_string(getpid()) + "-" +
                                          ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::create_directories(dir_);
  }
  ~CrashRecovery() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  const fs::path dir_;
};

// Index, then thumb, slide across a 20,000-point sphere with a small dead band, so nearly every
// glove sample makes a collision frame and a kill lands between frames as often as inside one.
fs::path slide_scene(const fs::path& dir, const fs::path& model) {
  const fs::path scene = dir / "slide.toml";
  std::ofstream(scene) << "[model]\npath = \"" << model.string() << "\"\n"
                       << "[material]\nG = 3e7\nnu = 0.45\n[deform]\nmode = \"push\"\ndelta_s = 0.01\n"
                       << "[heuristic]\nregion = 0.4\n"
                       << "[glove]\nbackend = \"sim\"\nfingers = [\"thumb\", \"index\"]\n"
                       << "[glove.sim]\nrate_hz = 80\nduration_s = 3.0\n"
                       << "[[glove.sim.script]]\nfinger = \"index\"\nkeyframes = [[0.0, 1.2, 0.0, 0.0], "
                          "[0.3, 0.95, 0.0, 0.0], [0.6, 0.9177, 0.2459, 0.0], [0.9, 0.8227, 0.475, 0.0], "
                          "[1.2, 0.6718, 0.6718, 0.0], [1.4, 0.8485, 0.8485, 0.0]]\n"
                       << "[[glove.sim.script]]\nfinger = \"thumb\"\nkeyframes = [[0.0, -1.2, 0.0, 0.0], "
                          "[1.5, -1.2, 0.0, 0.0], [1.8, -0.95, 0.0, 0.0], [2.1, -0.9177, -0.2459, 0.0], "
                          "[2.4, -0.8227, -0.475, 0.0], [2.6, -1.0392, -0.6, 0.0]]\n"
                       << "[loop]\nrate_hz = 1000\n[output]\nlog = \"" << (dir / "glove.lcmlog").string() << "\"\n";
  return scene;
}

TEST_F(CrashRecovery, AReRunKilledAtRandomMomentsRecoversTheCompletedRunUpToItsLastWholeFrame) {
  const fs::path model = dir_ / "sphere20k.ply";
  ASSERT_EQ(sculpt({"generate", "sphere", "--points", "20000", "--out", model.string()}, dir_ / "generate.txt"), 0);
  const fs::path scene = slide_scene(dir_, model);
  // The glove log the deterministic re-runs are fed from.
  ASSERT_EQ(sculpt({"run", scene.string(), "--duration", "3.2", "--quiet"}, dir_ / "record.txt"), 0)
      << file_contents(dir_ / "record.txt");
  const std::vector<std::string> rerun = {
      "replay", (dir_ / "glove.lcmlog").string(), "--model", model.string(), "--scene", scene.string(), "--mode",
      "rerun"};
  const fs::path complete = dir_ / "complete.lcmlog";
  std::vector<std::string> args = rerun;
  args.insert(args.end(), {"--record", complete.string(), "--json", (dir_ / "complete.json").string()});
  ASSERT_EQ(sculpt(args, dir_ / "complete.txt"), 0) << file_contents(dir_ / "complete.txt");
  const nlohmann::json done = nlohmann::json::parse(file_contents(dir_ / "complete.json"));
  ASSERT_EQ(done["rerun"]["record"]["dropped"].get<int>(), 0);
  ASSERT_GT(done["rerun"]["record"]["collisions"].get<int>(), 20);
  const std::uintmax_t full_size = size_of(complete);

  std::mt19937 random(20261201);  // fixed seed: the same moments every run
  std::uniform_real_distribution<double> moment(0.15, 0.85);
  int killed = 0;
  std::map<std::int64_t, int> last_frames;
  for (int k = 0; k < 5; ++k) {
    const fs::path cut = dir_ / ("cut" + std::to_string(k) + ".lcmlog");
    // The moment is a point in the log's growth, so it does not depend on this machine's speed.
    const auto threshold = static_cast<std::uintmax_t>(moment(random) * static_cast<double>(full_size));
    std::vector<std::string> argv = {SCULPT_BINARY};
    argv.insert(argv.end(), rerun.begin(), rerun.end());
    argv.insert(argv.end(), {"--record", cut.string()});
    test::ChildProcess child(argv, (dir_ / ("cut" + std::to_string(k) + ".txt")).string());
    ASSERT_TRUE(child.started());
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (size_of(cut) < threshold && std::chrono::steady_clock::now() < give_up) sched_yield();
    child.signal(SIGKILL);
    if (child.wait() == -1) ++killed;  // -1: died by the signal (0: it finished first)

    const WholeFrames truth = whole_frames_in(cut);
    const fs::path recovered = dir_ / ("recovered" + std::to_string(k) + ".ply");
    const fs::path report = dir_ / ("recovered" + std::to_string(k) + ".json");
    ASSERT_EQ(sculpt({"replay", cut.string(), "--model", model.string(), "--out", recovered.string(), "--json",
                      report.string()},
                     dir_ / "recover.txt"),
              0)
        << file_contents(dir_ / "recover.txt");
    const nlohmann::json r = nlohmann::json::parse(file_contents(report));
    EXPECT_EQ(r["transfer"]["events"].get<std::size_t>(), truth.events) << "kill " << k;
    const fs::path until = dir_ / ("until" + std::to_string(k) + ".ply");
    ASSERT_EQ(sculpt({"replay", complete.string(), "--model", model.string(), "--until-frame",
                      std::to_string(truth.last_frame), "--out", until.string()},
                     dir_ / "until.txt"),
              0)
        << file_contents(dir_ / "until.txt");
    EXPECT_TRUE(file_contents(recovered) == file_contents(until))
        << "kill " << k << " at " << size_of(cut) << " of " << full_size << " bytes, last whole frame "
        << truth.last_frame;
    ++last_frames[truth.last_frame];
    std::printf("[ kill ] %d: log cut at %ju of %ju bytes, last whole frame %lld, %zu events\n", k, size_of(cut),
                full_size, static_cast<long long>(truth.last_frame), truth.events);
  }
  EXPECT_GE(killed, 3) << "the re-runs finished before the kills: the moments tested nothing";
  EXPECT_GE(last_frames.size(), 2u) << "every kill left the same frames";
}

TEST_F(CrashRecovery, ARealTimeRunKilledRecoversAFiniteModelHoldingEveryCompleteCollision) {
  std::string text = file_contents(fs::path(SCULPT_SOURCE_DIR) / "scenes" / "sphere-squeeze.toml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"../data/", std::string(SCULPT_SOURCE_DIR) + "/data/"},
        {"../out/", dir_.string() + "/"}}) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  const fs::path scene = dir_ / "squeeze.toml";
  std::ofstream(scene) << text;
  std::mt19937 random(9);
  // The fingers touch the sphere from about 0.8 s on and hold until 2 s; the kill lands a random
  // moment (up to 1 s) after the first collision reached the disk, so while they press or hold.
  // A fixed delay from the start also measured how long the run took to start: a sanitizer
  // build under a parallel test's load once wrote nothing in the 1.3 s drawn.
  const auto delay = std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 1000)(random));
  const fs::path log = dir_ / "sphere-squeeze.lcmlog";
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "10", "--quiet"},
                         (dir_ / "run.txt").string());
  ASSERT_TRUE(run.started());
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!(fs::exists(log) && whole_frames_in(log).events > 0) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::this_thread::sleep_for(delay);
  run.signal(SIGKILL);
  ASSERT_EQ(run.wait(), -1) << "the run was not killed: " << file_contents(dir_ / "run.txt");

  const WholeFrames truth = whole_frames_in(log);
  ASSERT_GT(truth.events, 0u) << "no collision reached the disk before the kill";
  const fs::path recovered = dir_ / "recovered.ply";
  ASSERT_EQ(sculpt({"replay", log.string(), "--model", std::string(SCULPT_SOURCE_DIR) + "/data/sphere_3203.ply",
                    "--out", recovered.string(), "--json", (dir_ / "recovered.json").string()},
                   dir_ / "recover.txt"),
            0)
      << file_contents(dir_ / "recover.txt");
  const nlohmann::json r = nlohmann::json::parse(file_contents(dir_ / "recovered.json"));
  EXPECT_EQ(r["transfer"]["events"].get<std::size_t>(), truth.events);
  EXPECT_EQ(r["model_match"], "recording");
  const deform::PointModel model = deform::read_model(recovered.string());
  ASSERT_EQ(model.size(), 3203u);
  for (std::size_t i = 0; i < model.size(); ++i) {
    ASSERT_TRUE(std::isfinite(model.x[i]) && std::isfinite(model.y[i]) && std::isfinite(model.z[i])) << "point " << i;
  }
  std::printf("[ kill ] real-time run killed after %lld ms: %zu complete collision events recovered\n",
              static_cast<long long>(delay.count()), truth.events);
}

}  // namespace
}  // namespace sculpt
