// The event log against the station and LCM's own tools, in separate processes: every
// collision the loop counts is in the durable log and on the live channel (as a stock
// lcm-logger captures it), a minute of five fingers at 1 kHz loses nothing, and a log played by
// the stock lcm-logplayer drives the station through its LCM glove backend.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"

namespace sculpt {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::map<std::string, std::size_t> count_channels(const fs::path& path) {
  std::map<std::string, std::size_t> counts;
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    if (r == logging::EventLogReader::Result::kEvent) ++counts[event.channel];
  }
  return counts;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

// A bundled scene rewritten for a test: absolute model path, outputs into `dir`, and extra
// sections appended.
fs::path scene_in(const fs::path& dir, const std::string& name, const std::string& extra) {
  std::string text = slurp(fs::path(SCULPT_SOURCE_DIR) / "scenes" / (name + ".toml"));
  replace_all(text, "../data/", std::string(SCULPT_SOURCE_DIR) + "/data/");
  replace_all(text, "../out/", dir.string() + "/");
  const fs::path scene = dir / (name + ".toml");
  std::ofstream(scene) << text << "\n" << extra << "\n";
  return scene;
}

std::string unique_url(int offset) {
  return "udpm://239.255.76.67:" + std::to_string(7900 + offset + getpid() % 100 * 3) + "?ttl=0";
}

class EventLogHil : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sculpt-log-hil-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(EventLogHil, EveryCollisionIsInTheDurableLogAndOnTheLiveChannel) {
  const std::string url = unique_url(0);
  const fs::path scene = scene_in(dir_, "sphere-squeeze", "[lcm]\npublish = true\nurl = \"" + url + "\"");
  const fs::path live = dir_ / "live.lcmlog";
  test::ChildProcess logger({"lcm-logger", "--lcm-url=" + url, "-f", "-q", live.string()}, dir_ / "logger.txt");
  ASSERT_TRUE(logger.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // a late subscriber misses messages
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "5", "--quiet"}, dir_ / "run.txt");
  ASSERT_EQ(run.wait(), 0) << slurp(dir_ / "run.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  logger.signal(SIGINT);
  logger.wait();

  const nlohmann::json r = nlohmann::json::parse(slurp(dir_ / "sphere-squeeze.json"));
  const std::size_t collisions = r["collisions"].get<std::size_t>();
  ASSERT_GT(collisions, 0u);
  const auto durable = count_channels(dir_ / "sphere-squeeze.lcmlog");
  EXPECT_EQ(durable.at(logging::kCollisionChannel), collisions);
  EXPECT_EQ(durable.at(logging::kTickChannel), r["ticks"].get<std::size_t>());
  EXPECT_EQ(r["recording"]["log"]["dropped"].get<int>(), 0);
  const auto captured = count_channels(live);
  ASSERT_TRUE(captured.count(logging::kCollisionChannel)) << "lcm-logger captured no collision";
  EXPECT_EQ(captured.at(logging::kCollisionChannel), collisions);
  std::printf("[ log ] %zu collisions: %zu in the durable log, %zu captured live by lcm-logger\n", collisions,
              durable.at(logging::kCollisionChannel), captured.at(logging::kCollisionChannel));
}

TEST_F(EventLogHil, AMinuteOfFiveFingersAtOneKilohertzLosesNothing) {
  const fs::path scene = scene_in(dir_, "sphere-five", "");
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "60", "--quiet"}, dir_ / "run.txt");
  ASSERT_EQ(run.wait(std::chrono::seconds(180)), 0) << slurp(dir_ / "run.txt");
  const nlohmann::json r = nlohmann::json::parse(slurp(dir_ / "sphere-five.json"));
  const auto& log = r["recording"]["log"];
  std::printf("[ log ] 60 s: %s\n", r["recording"].dump().c_str());
  EXPECT_EQ(log["dropped"].get<int>(), 0);
  EXPECT_EQ(log["write_errors"].get<int>(), 0);
  const auto durable = count_channels(dir_ / "sphere-five.lcmlog");
  EXPECT_EQ(durable.at(logging::kTickChannel), r["ticks"].get<std::size_t>());
  EXPECT_GT(r["ticks"].get<double>(), 30000.0);  // gross failure only: a shared machine
  EXPECT_EQ(durable.at(logging::kCollisionChannel), r["collisions"].get<std::size_t>());
  EXPECT_EQ(durable.at(logging::kGloveChannel), r["samples_taken"].get<std::size_t>());
}

TEST_F(EventLogHil, StockLogplayerDrivesTheStationThroughItsLcmBackend) {
  const fs::path scene = scene_in(dir_, "sphere-press", "");
  test::ChildProcess record({SCULPT_BINARY, "run", scene.string(), "--duration", "4", "--quiet"}, dir_ / "record.txt");
  ASSERT_EQ(record.wait(), 0) << slurp(dir_ / "record.txt");
  const nlohmann::json recorded = nlohmann::json::parse(slurp(dir_ / "sphere-press.json"));
  // The playback run writes its own log at the scene's path: play a copy of the recording.
  fs::copy_file(dir_ / "sphere-press.lcmlog", dir_ / "recorded.lcmlog");

  const std::string url = unique_url(1);
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--lcm", url, "--duration", "7", "--quiet",
                           "--json", (dir_ / "played.json").string(), "--out", (dir_ / "played.ply").string()},
                          dir_ / "run.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  test::ChildProcess player({"lcm-logplayer", "--lcm-url=" + url, (dir_ / "recorded.lcmlog").string()},
                            dir_ / "player.txt");
  ASSERT_TRUE(player.started());
  EXPECT_EQ(player.wait(), 0) << slurp(dir_ / "player.txt");
  ASSERT_EQ(run.wait(), 0) << slurp(dir_ / "run.txt");
  const nlohmann::json played = nlohmann::json::parse(slurp(dir_ / "played.json"));
  std::printf("[ log ] recorded %d samples and %d collisions; played back: %d samples, %d collisions\n",
              recorded["samples_taken"].get<int>(), recorded["collisions"].get<int>(),
              played["glove_samples"].get<int>(), played["collisions"].get<int>());
  // UDP may drop a few; the press must come through.
  EXPECT_GT(played["glove_samples"].get<int>(), recorded["samples_taken"].get<int>() * 9 / 10);
  EXPECT_GT(played["collisions"].get<int>(), 0);
}

}  // namespace
}  // namespace sculpt
