// The station with its LCM session recorder, as `sculpt run` drives it: the whole tick,
// recorder included, allocates nothing from the first tick; every collision the station counts
// is in the durable log, built by the same code transfer uses; and the log applied to the base
// model gives back the station's model exactly (the log is the edit history).
#include "sculpt/rt/session_recorder.hpp"

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/rt/transfer.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "station_fixtures.hpp"
#include "support/allocation_counter.hpp"

namespace sculpt::rt {
namespace {

using namespace test_fixtures;
namespace fs = std::filesystem;

std::vector<logging::CollisionRecord> logged_collisions(const fs::path& path, std::vector<std::int64_t>& ticks) {
  std::vector<logging::CollisionRecord> out;
  ticks.clear();
  logging::EventLogReader reader(path.string());
  logging::LogEvent event;
  for (auto r = reader.next(event); r != logging::EventLogReader::Result::kEnd; r = reader.next(event)) {
    EXPECT_EQ(r, logging::EventLogReader::Result::kEvent) << reader.error();
    if (event.channel == logging::kTickChannel) {
      sculpt_lcm::tick_stats_t tick{};
      std::string error;
      EXPECT_TRUE(logging::decode(event, tick, error)) << error;
      ticks.push_back(tick.tick);
    }
    if (event.channel != logging::kCollisionChannel) continue;
    sculpt_lcm::collision_event_t message;
    std::string error;
    logging::CollisionRecord record;
    EXPECT_TRUE(logging::decode(event, message, error)) << error;
    EXPECT_TRUE(logging::from_lcm(message, record)) << "invalid fields at byte offset " << event.offset;
    out.push_back(record);
  }
  return out;
}

TEST(SessionRecorder, TheRecordedTickAllocatesNothingAndTheLogRebuildsTheModel) {
  const fs::path dir = fs::temp_directory_path() / ("sculpt-recorder-" + std::to_string(getpid()));
  fs::create_directories(dir);
  Scene scene;
  scene.output.log = (dir / "session.lcmlog").string();
  std::unique_ptr<SessionRecorder> recorder = make_session_recorder(scene);
  ASSERT_NE(recorder, nullptr);

  deform::PointModel sphere = deform::make_sphere();
  const deform::PointModel base = sphere;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  Station station(sphere, press_settings(), std::move(glove), nullptr);
  station.set_recorder(recorder.get());
  recorder->start();
  station.start();

  // Press in, slide across the pole while pushing deeper, release: 1 kHz ticks, a sample every 5 ticks.
  std::int64_t now = 0;
  std::uint64_t ticks = 0;
  std::uint64_t allocations = 0;
  {
    test::AllocationCounter counter;  // from the very first tick
    for (int i = 0; i < 90; ++i) {
      const double z = i < 30 ? 1.3 - 0.012 * i : i < 60 ? 0.94 - 0.003 * (i - 30) : 0.85 + 0.015 * (i - 60);
      const double x = i < 30 ? 0.0 : i < 60 ? 0.01 * (i - 30) : 0.3;
      for (int t = 0; t < 5; ++t) {
        now += kMs;
        if (t == 0) g->feed({x, 0.0, z}, now, static_cast<std::uint64_t>(now / 1000));
        const TickReport& r = station.tick(now, 200'000);
        recorder->tick(r, 0, 0, 1.0);  // as run_station does
        ++ticks;
      }
    }
    allocations = counter.count();
  }
  station.stop();
  recorder->stop();
  EXPECT_EQ(allocations, 0u) << "the recorded tick allocated";

  const RecordingCounts counts = recorder->counts();
  EXPECT_EQ(counts.log_dropped, 0u);
  EXPECT_EQ(counts.write_errors, 0u);
  std::vector<std::int64_t> logged_ticks;
  const std::vector<logging::CollisionRecord> events = logged_collisions(*scene.output.log, logged_ticks);
  // The log keeps the eventful ticks and a quiet one every 100 ms (100 ticks at 1 kHz), and
  // counts the rest: every tick accounted for, every collision's tick kept, no longer gap.
  EXPECT_EQ(logged_ticks.size() + counts.ticks_left_out, ticks);
  EXPECT_EQ(counts.ticks, logged_ticks.size());
  EXPECT_GT(counts.ticks_left_out, ticks / 2) << "the quiet ticks were kept";
  ASSERT_FALSE(logged_ticks.empty());
  EXPECT_EQ(logged_ticks.front(), 0);
  for (std::size_t k = 1; k < logged_ticks.size(); ++k) {
    EXPECT_GT(logged_ticks[k], logged_ticks[k - 1]);
    EXPECT_LE(logged_ticks[k] - logged_ticks[k - 1], 100) << "a gap of quiet ticks longer than the interval";
  }
  // A stroke of many collisions. How many depends on the auto region, which is sized from the
  // machine's measured speed: 10 to 17 seen (the collision test's surface reads the dent's rim).
  ASSERT_GE(station.totals().collisions, 8u);
  ASSERT_EQ(events.size(), station.totals().collisions);
  for (const logging::CollisionRecord& e : events) {
    EXPECT_TRUE(std::binary_search(logged_ticks.begin(), logged_ticks.end(), e.tick))
        << "collision tick " << e.tick << " left out of the log";
    EXPECT_EQ(e.hand, 0);
    EXPECT_EQ(e.finger, 1);
    EXPECT_NE(e.utime, 0);
    // Relative: |Aw - b| / |b| of the least-squares solve, never above 1 (w = 0 gives 1).
    EXPECT_GE(e.residual, 0.0);
    EXPECT_LE(e.residual, 1.0);
  }

  deform::PointModel replayed = base;
  transfer(replayed, events);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    moved += base.position(i) != sphere.position(i);
    ASSERT_EQ(replayed.position(i), sphere.position(i)) << "point " << i;
    ASSERT_EQ(replayed.normal(i), sphere.normal(i)) << "point " << i;
  }
  EXPECT_GT(moved, 0u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sculpt::rt
