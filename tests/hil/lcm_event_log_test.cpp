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

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "support/bundled_scene.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/fingertip_state_t.hpp"
#include "sculpt_lcm/glove_sample_t.hpp"
#include "sculpt_lcm/haptic_command_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "support/file_contents.hpp"

namespace sculpt {
namespace {

namespace fs = std::filesystem;

using test::file_contents;

std::map<std::string, std::size_t> count_channels(const fs::path& path) {
  std::map<std::string, std::size_t> counts;
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    if (r == logging::EventLogReader::Result::kEvent) ++counts[event.channel];
  }
  return counts;
}

// Whether a log being written holds a tick record yet (false while it does not exist).
bool has_tick(const fs::path& path) {
  if (!fs::exists(path)) return false;
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  while (reader.next(event) == logging::EventLogReader::Result::kEvent) {
    if (event.channel == logging::kTickChannel) return true;
  }
  return false;
}

// Every payload on one channel, as bytes, in file order.
std::multiset<std::string> payloads_on(const fs::path& path, const std::string& channel) {
  std::multiset<std::string> payloads;
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    if (r == logging::EventLogReader::Result::kEvent && event.channel == channel)
      payloads.emplace(event.data.begin(), event.data.end());
  }
  return payloads;
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
  const fs::path scene =
      test::copy_bundled_scene(dir_, "sphere-squeeze", "[lcm]\npublish = true\nurl = \"" + url + "\"");
  const fs::path live = dir_ / "live.lcmlog";
  test::ChildProcess logger({"lcm-logger", "--lcm-url=" + url, "-f", "-q", live.string()}, dir_ / "logger.txt");
  ASSERT_TRUE(logger.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // a late subscriber misses messages
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "5", "--quiet"}, dir_ / "run.txt");
  ASSERT_EQ(run.wait(), 0) << file_contents(dir_ / "run.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  logger.signal(SIGINT);
  logger.wait();

  const nlohmann::json r = nlohmann::json::parse(file_contents(dir_ / "sphere-squeeze.json"));
  const std::size_t collisions = r["collisions"].get<std::size_t>();
  ASSERT_GT(collisions, 0u);
  const auto durable = count_channels(dir_ / "sphere-squeeze.lcmlog");
  EXPECT_EQ(durable.at(logging::kCollisionChannel), collisions);
  // Every tick is either in the log or counted as a quiet one it left out (TickLogFilter).
  EXPECT_EQ(durable.at(logging::kTickChannel), r["recording"]["log"]["ticks"].get<std::size_t>());
  EXPECT_EQ(durable.at(logging::kTickChannel) + r["recording"]["log"]["ticks_left_out"].get<std::size_t>(),
            r["ticks"].get<std::size_t>());
  EXPECT_EQ(r["recording"]["log"]["dropped"].get<int>(), 0);
  // The live channel is UDP, which may drop a datagram on a loaded machine (the durable log is
  // the record for that reason): every event captured live must be, byte for byte, one the
  // durable log holds, and at most one in a hundred (or one) may be missing.
  const auto in_log = payloads_on(dir_ / "sphere-squeeze.lcmlog", logging::kCollisionChannel);
  const auto captured = payloads_on(live, logging::kCollisionChannel);
  ASSERT_FALSE(captured.empty()) << "lcm-logger captured no collision";
  std::size_t not_in_log = 0;
  for (auto it = captured.begin(); it != captured.end(); it = captured.upper_bound(*it)) {
    if (captured.count(*it) > in_log.count(*it)) not_in_log += captured.count(*it) - in_log.count(*it);
  }
  EXPECT_EQ(not_in_log, 0u) << "captured live but not in the durable log";
  EXPECT_LE(captured.size(), collisions);
  EXPECT_LE(collisions - std::min(collisions, captured.size()), std::max<std::size_t>(1, collisions / 100));
  std::printf("[ log ] %zu collisions: %zu in the durable log, %zu captured live by lcm-logger\n", collisions,
              durable.at(logging::kCollisionChannel), captured.size());
}

// A minute of real time in the Release pass. The sanitizer passes run the same code paths for a
// quarter of it: their findings come from what runs, not from how long, and the two minutes saved
// keep the test command inside its budget.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr int kLongRunSeconds = 15;
#else
constexpr int kLongRunSeconds = 60;
#endif

TEST_F(EventLogHil, AMinuteOfFiveFingersAtOneKilohertzLosesNothing) {
  const fs::path scene = test::copy_bundled_scene(dir_, "sphere-five");
  test::ChildProcess run(
      {SCULPT_BINARY, "run", scene.string(), "--duration", std::to_string(kLongRunSeconds), "--quiet"},
      dir_ / "run.txt");
  ASSERT_EQ(run.wait(std::chrono::seconds(180)), 0) << file_contents(dir_ / "run.txt");
  const nlohmann::json r = nlohmann::json::parse(file_contents(dir_ / "sphere-five.json"));
  const auto& log = r["recording"]["log"];
  std::printf("[ log ] %d s: %s\n", kLongRunSeconds, r["recording"].dump().c_str());
  EXPECT_EQ(log["dropped"].get<int>(), 0);
  EXPECT_EQ(log["write_errors"].get<int>(), 0);
  const auto durable = count_channels(dir_ / "sphere-five.lcmlog");
  EXPECT_EQ(durable.at(logging::kTickChannel) + log["ticks_left_out"].get<std::size_t>(),
            r["ticks"].get<std::size_t>());
  EXPECT_GT(r["ticks"].get<double>(), 500.0 * kLongRunSeconds);  // gross failure only: a shared machine
  EXPECT_EQ(durable.at(logging::kCollisionChannel), r["collisions"].get<std::size_t>());
  EXPECT_EQ(durable.at(logging::kGloveChannel), r["samples_taken"].get<std::size_t>());
}

TEST_F(EventLogHil, StockLogplayerDrivesTheStationThroughItsLcmBackend) {
  const fs::path scene = test::copy_bundled_scene(dir_, "sphere-press");
  test::ChildProcess record({SCULPT_BINARY, "run", scene.string(), "--duration", "4", "--quiet"}, dir_ / "record.txt");
  ASSERT_EQ(record.wait(), 0) << file_contents(dir_ / "record.txt");
  const nlohmann::json recorded = nlohmann::json::parse(file_contents(dir_ / "sphere-press.json"));
  // The playback run writes its own log at the scene's path: play the recording from elsewhere.
  const fs::path own_log = dir_ / "sphere-press.lcmlog";
  fs::rename(own_log, dir_ / "recorded.lcmlog");

  const std::string url = unique_url(1);
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--lcm", url, "--duration", "7", "--quiet", "--json",
                          (dir_ / "played.json").string(), "--out", (dir_ / "played.ply").string()},
                         dir_ / "run.txt");
  // Samples played before the station has subscribed are lost, and a fixed 0.7 s was once too
  // short for a ThreadSanitizer build to start: play once its loop ticks (its first tick in its
  // own log; the glove source subscribes before the loop starts).
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!has_tick(own_log) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(has_tick(own_log)) << "the station did not start in 60 s: " << file_contents(dir_ / "run.txt");
  test::ChildProcess player({"lcm-logplayer", "--lcm-url=" + url, (dir_ / "recorded.lcmlog").string()},
                            dir_ / "player.txt");
  ASSERT_TRUE(player.started());
  EXPECT_EQ(player.wait(), 0) << file_contents(dir_ / "player.txt");
  ASSERT_EQ(run.wait(), 0) << file_contents(dir_ / "run.txt");
  const nlohmann::json played = nlohmann::json::parse(file_contents(dir_ / "played.json"));
  std::printf("[ log ] recorded %d samples and %d collisions; played back: %d samples, %d collisions\n",
              recorded["samples_taken"].get<int>(), recorded["collisions"].get<int>(),
              played["glove_samples"].get<int>(), played["collisions"].get<int>());
  // UDP may drop a few; the press must come through.
  EXPECT_GT(played["glove_samples"].get<int>(), recorded["samples_taken"].get<int>() * 9 / 10);
  EXPECT_GT(played["collisions"].get<int>(), 0);
}

// Issue 8's must-show: the one-finger press with an LCM haptic sink clamped at 4 N, captured by a
// stock lcm-logger in another process. While the finger holds still in the surface for one
// second at 1 kHz the glove gets a command every tick (500 or more is the bar: a shared
// machine may miss some periods), no force is ever above the clamp, `tick` is the loop's tick
// (strictly increasing), and the last command releases the finger.
TEST_F(EventLogHil, StockLoggerCapturesABoundedHapticCommandEveryTickOfTheHold) {
  const std::string url = unique_url(2);
  const fs::path scene = test::copy_bundled_scene(
      dir_, "sphere-press", "[haptic]\nsink = \"lcm\"\nmax_force = 4.0\n[haptic.lcm]\nurl = \"" + url + "\"");
  const fs::path live = dir_ / "haptic.lcmlog";
  test::ChildProcess logger({"lcm-logger", "--lcm-url=" + url, "-f", "-q",
                             "--channel=" + std::string(logging::kHapticChannel), live.string()},
                            dir_ / "logger.txt");
  ASSERT_TRUE(logger.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // a late subscriber misses messages
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "3.5", "--quiet"}, dir_ / "run.txt");
  ASSERT_EQ(run.wait(), 0) << file_contents(dir_ / "run.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  logger.signal(SIGINT);
  logger.wait();

  struct Command {
    std::int64_t utime, tick;
    double force;  // the index finger's magnitude, newtons
    bool in_contact;
  };
  std::vector<Command> commands;
  logging::EventLogReader reader(live.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    if (r != logging::EventLogReader::Result::kEvent || event.channel != logging::kHapticChannel) continue;
    sculpt_lcm::haptic_command_t m{};
    ASSERT_GT(m.decode(event.data.data(), 0, static_cast<int>(event.data.size())), 0) << "undecodable command";
    const float* f = m.force[1];  // index finger
    commands.push_back({m.utime, m.tick, std::sqrt(double(f[0]) * f[0] + double(f[1]) * f[1] + double(f[2]) * f[2]),
                        (m.active_mask & 0b10) != 0});
  }
  ASSERT_FALSE(commands.empty()) << "lcm-logger captured no haptic command";

  double peak = 0.0;
  std::size_t in_contact = 0;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    peak = std::max(peak, commands[i].force);
    in_contact += commands[i].in_contact;
    if (i > 0) {
      ASSERT_GT(commands[i].tick, commands[i - 1].tick) << "command " << i;
    }
  }
  EXPECT_LE(peak, 4.0 + 1e-6);
  EXPECT_GT(peak, 1.0) << "the press should be felt";
  // The most in-contact commands in any one second of wall time: the hold.
  std::size_t best = 0;
  for (std::size_t begin = 0, end = 0; end < commands.size(); ++end) {
    while (commands[end].utime - commands[begin].utime >= 1'000'000) ++begin;
    std::size_t n = 0;
    for (std::size_t i = begin; i <= end; ++i) n += commands[i].in_contact;
    best = std::max(best, n);
  }
  EXPECT_GE(best, 500u);
  // The station's own account: it published at least what the logger heard (UDP may drop).
  const nlohmann::json summary = nlohmann::json::parse(file_contents(dir_ / "sphere-press.json"));
  EXPECT_EQ(summary["haptic"]["sink"], "lcm");
  EXPECT_GE(summary["haptic"]["delivered"].get<std::size_t>(), commands.size());
  EXPECT_EQ(summary["haptic"]["dropped"].get<std::size_t>(), 0u);
  EXPECT_FALSE(commands.back().in_contact);
  EXPECT_EQ(commands.back().force, 0.0) << "the finger let go: the last command must release it";
  std::printf("[ haptic ] lcm-logger captured %zu commands, %zu in contact, %zu in the best second, peak %.3f N\n",
              commands.size(), in_contact, best, peak);
}

// The fields of a recorded log mean what docs/lcm-types.md says: every utime is wall-clock time
// within the run (never CLOCK_MONOTONIC, which is seconds since boot); budget_us is the time
// left to the deadline, never more than the period; the haptic, fingertip and collision ticks
// are loop ticks (each one a tick that has its own tick_stats_t, with the log keeping every tick
// here); in the force form the weights are the effective force, in shear-modulus units x model
// units squared.
TEST_F(EventLogHil, RecordedFieldsMeanWhatTheDocsSay) {
  const fs::path scene = test::copy_bundled_scene(
      dir_, "sphere-press", "[haptic]\nsink = \"lcm\"\n[haptic.lcm]\nurl = \"" + unique_url(3) + "\"",
      {{"form = \"scale\"", "form = \"force\""},
       {"log = \"../out/sphere-press.lcmlog\"", "log = \"../out/sphere-press.lcmlog\"\ntick_interval_ms = 0"}});
  const auto wall_us = [] {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
  };
  const std::int64_t start = wall_us();
  test::ChildProcess run({SCULPT_BINARY, "run", scene.string(), "--duration", "3.5", "--quiet"}, dir_ / "run.txt");
  ASSERT_EQ(run.wait(), 0) << file_contents(dir_ / "run.txt");
  const std::int64_t end = wall_us();

  std::set<std::int64_t> ticks;
  std::vector<std::int64_t> joined;  // ticks named by the other channels
  std::size_t counted = 0, collisions = 0, budgets_below_period = 0;
  logging::EventLogReader reader((dir_ / "sphere-press.lcmlog").string());
  logging::LogEvent event;
  std::string error;
  const auto within_run = [&](std::int64_t utime, const char* what) {
    EXPECT_GE(utime, start) << what << " utime is not wall-clock time of this run";
    EXPECT_LE(utime, end) << what;
  };
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    ASSERT_EQ(r, logging::EventLogReader::Result::kEvent) << reader.error();
    ++counted;
    within_run(event.utime, "the log's event");
    if (event.channel == logging::kTickChannel) {
      sculpt_lcm::tick_stats_t m{};
      ASSERT_TRUE(logging::decode(event, m, error)) << error;
      within_run(m.utime, "tick_stats_t");
      EXPECT_TRUE(ticks.insert(m.tick).second) << "tick " << m.tick << " twice";
      // Negative when the tick began after its deadline (a late wake-up on a loaded machine).
      EXPECT_LE(m.budget_us, 1000.0f + 1e-3f) << "budget_us is the time left, at most the 1 ms period";
      budgets_below_period += m.budget_us < 1000.0f;
    } else if (event.channel == logging::kHapticChannel) {
      sculpt_lcm::haptic_command_t m{};
      ASSERT_TRUE(logging::decode(event, m, error)) << error;
      within_run(m.utime, "haptic_command_t");
      joined.push_back(m.tick);
    } else if (event.channel == logging::kFingertipChannel) {
      sculpt_lcm::fingertip_state_t m{};
      ASSERT_TRUE(logging::decode(event, m, error)) << error;
      within_run(m.utime, "fingertip_state_t");
      joined.push_back(m.tick);
    } else if (event.channel == logging::kGloveChannel) {
      sculpt_lcm::glove_sample_t m{};
      ASSERT_TRUE(logging::decode(event, m, error)) << error;
      within_run(m.utime, "glove_sample_t");
    } else if (event.channel == logging::kCollisionChannel) {
      sculpt_lcm::collision_event_t m{};
      ASSERT_TRUE(logging::decode(event, m, error)) << error;
      within_run(m.utime, "collision_event_t");
      joined.push_back(m.tick);
      ++collisions;
      ASSERT_EQ(m.form, sculpt_lcm::collision_event_t::FORM_FORCE);
      double weight = 0.0;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(m.weights[k], m.effective_force[k]) << "force form: the weights are the effective force";
        weight += m.weights[k] * m.weights[k];
      }
      // |f| ~ G |u| r: G = 3e7, a press of a few hundredths over a patch of ~0.1; far from 1.
      EXPECT_GT(std::sqrt(weight), 1e3) << "weights are not dimensionless";
    }
  }
  ASSERT_GT(collisions, 0u);
  ASSERT_FALSE(ticks.empty());
  for (std::int64_t t : joined) ASSERT_TRUE(ticks.count(t)) << "tick " << t << " is not a loop tick";
  EXPECT_GT(budgets_below_period, ticks.size() / 2) << "the time left is below the period on most ticks";
  std::printf("[ log ] %zu events, %zu ticks, %zu collisions, %zu joined on tick\n", counted, ticks.size(), collisions,
              joined.size());
}

}  // namespace
}  // namespace sculpt
