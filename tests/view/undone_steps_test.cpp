// Steps the deformer split or undid (a fold, README *Stability*) as the live channel carries
// them: every tick's collision count is what its published events hold, so a viewer following
// the channel with nothing lost finds no gap, never says DIVERGED, and its copy is the station's
// model byte for byte. A wholly undone step must count no collision, or the viewer would take
// the events it never got for a loss.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "frame_follower.hpp"
#include "rt/station_fixtures.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/rt/collision_records.hpp"
#include "sculpt/rt/station.hpp"
#include "sculpt/rt/station_recorder.hpp"
#include "sculpt/rt/transfer.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::test {
namespace {

using rt::test_fixtures::FakeGlove;
using rt::test_fixtures::kMs;

// What a live channel would carry, kept in memory: every collision event and every tick.
class ChannelRecorder final : public rt::StationRecorder {
 public:
  struct Tick {
    std::int64_t tick;
    int collisions;
    bool undone;  // the tick's step ran and none of its frames was kept
  };

  explicit ChannelRecorder(const rt::Station* station) : station_(station) {}

  void glove_sample(const hal::GloveSample&) noexcept override {}
  void fingertips(std::uint64_t, std::span<const rt::FingerId>, std::span<const rt::FingerState>,
                  std::span<const bool>) noexcept override {}
  void haptic(const hal::HapticCommand&) noexcept override {}
  void frame(const rt::FrameRecord& frame) noexcept override {
    logging::CollisionRecord out[8];
    const std::size_t n = rt::frame_collision_records(frame, out);
    events.insert(events.end(), out, out + n);
  }
  void tick(const rt::TickReport& report, std::uint64_t, std::uint64_t, double) noexcept override {
    const bool undone = report.frame && station_->last_frame().rejected;
    ticks.push_back({static_cast<std::int64_t>(report.tick), static_cast<int>(report.collisions), undone});
  }

  std::vector<logging::CollisionRecord> events;
  std::vector<Tick> ticks;

 private:
  const rt::Station* station_;
};

TEST(UndoneSteps, AViewerFollowingTheLiveChannelOfSplitAndUndoneStepsStaysExact) {
  const deform::PointModel base = deform::make_sphere();
  deform::PointModel sphere = base;
  rt::StationSettings s = rt::test_fixtures::press_settings();
  s.region.kind = rt::RegionPolicy::Kind::kGlobal;
  s.delta_s = 0.005;
  // Only Δd keeps the source off the surface, as in the thesis, and it is a thirtieth of the
  // spacing: deep steps from so close a source fold, and are split into substeps or undone.
  s.deform.contact.min_source_distance = 0.002;
  s.deform.guards.clearance_ratio = 0.0;
  s.deform.guards.finger_radius_clearance = false;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  rt::Station station(sphere, s, std::move(glove), nullptr);
  ChannelRecorder channel(&station);
  station.set_recorder(&channel);
  station.start();

  // The index finger comes down on the pole in steps that grow deeper, lifts off, and does it
  // again beside the first dent: one sample every 5 ticks of a 1 kHz loop.
  std::int64_t now = 0;
  const auto sample = [&](const deform::Vec3& tip) {
    for (int t = 0; t < 5; ++t) {
      now += kMs;
      if (t == 0) g->feed(tip, now, static_cast<std::uint64_t>(now / 1000));
      channel.tick(station.tick(now, 1'000'000), 0, 0, 0.0);  // as run_station() does
    }
  };
  for (const double x : {0.0, 0.12}) {
    double z = 1.05;
    for (int k = 1; k <= 8; ++k) sample({x, 0.0, z -= 0.05 * k});
    for (int k = 0; k < 10; ++k) sample({x, 0.0, 1.4});
  }
  station.stop();

  const deform::GuardCounts& guards = station.totals().guards;
  std::size_t undone_with_collisions = 0, undone = 0;
  for (const ChannelRecorder::Tick& t : channel.ticks) {
    undone += t.undone ? 1 : 0;
    undone_with_collisions += t.undone && t.collisions > 0 ? 1 : 0;
  }
  std::set<std::int64_t> ids;
  for (const logging::CollisionRecord& e : channel.events) ids.insert(e.frame_id);
  std::printf("[ view ] %zu ticks, %zu frames logged, %llu fold splits, %llu substeps undone, %zu steps undone\n",
              channel.ticks.size(), ids.size(), static_cast<unsigned long long>(guards.fold_splits),
              static_cast<unsigned long long>(guards.fold_rejected), undone);
  ASSERT_GT(guards.fold_splits, 0u) << "the strokes must split a step";
  ASSERT_GT(undone, 0u) << "the strokes must undo a whole step";
  EXPECT_EQ(undone_with_collisions, 0u) << "an undone step counted collisions it never published";

  // Every tick, then every event, in the order the station sent them (a lossless channel).
  deform::PointModel copy = base;
  rt::TransferOptions options;
  options.field = s.deform.field;
  rt::FrameTransfer transfer(copy, options);
  view::FrameFollower follower([&](std::span<const logging::CollisionRecord> f) { transfer.apply(f); });
  std::size_t next_event = 0;
  for (const ChannelRecorder::Tick& t : channel.ticks) {
    while (next_event < channel.events.size() && channel.events[next_event].tick <= t.tick) {
      follower.collision(channel.events[next_event++], 0);
    }
    follower.tick(t.tick, t.collisions, 0);
  }
  follower.finish();
  EXPECT_FALSE(follower.diverged()) << follower.diverged_frames() << " frames";
  EXPECT_EQ(follower.gaps(), 0u);
  EXPECT_EQ(follower.frames_applied(), ids.size());
  EXPECT_TRUE(same_position_bytes(copy, sphere)) << "the viewer's copy differs from the station's model";
}

}  // namespace
}  // namespace sculpt::test
