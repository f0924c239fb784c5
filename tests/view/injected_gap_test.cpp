// A recorded session fed to the follower as the live channel would bring it, with one collision
// frame dropped as a UDP burst would drop it: the gap is found and counted, and with the durable
// log as catch-up the viewer's copy is again exactly the station's output model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <vector>

#include "catch_up_log.hpp"
#include "frame_follower.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station_setup.hpp"
#include "sculpt/rt/transfer.hpp"
#include "session_log.hpp"
#include "view/view_session.hpp"

namespace sculpt::test {
namespace {

class InjectedGap : public SessionFolder {
 protected:
  // The session's base model as sculpt view loads it, with `events` (all but `dropped`)
  // and every tick fed to a follower; returns the follower's copy as it is written to disk.
  deform::PointModel follow(const fs::path& scene_path, const view::SessionLog& log, std::int64_t dropped,
                            bool catch_up, view::FrameFollower** out = nullptr) {
    const rt::Scene scene = rt::load_scene(scene_path.string());
    rt::StationSetup setup = rt::prepare_station(scene);
    rt::TransferOptions options;
    options.field = setup.settings.deform.field;
    rt::FrameTransfer transfer(setup.model, options);
    view::FrameFollower::CatchUpSource source;
    const std::string log_path = (dir_ / "sphere-press.lcmlog").string();
    if (catch_up) {
      source = [log = std::make_shared<view::CatchUpLog>(log_path)](std::int64_t a, std::int64_t b) {
        return log->events(a, b);
      };
    }
    follower_ = std::make_unique<view::FrameFollower>(
        [&](std::span<const logging::CollisionRecord> f) { transfer.apply(f); }, source);
    for (const view::TickSeen& t : log.ticks) follower_->tick(t.tick, t.collisions, 0);
    for (const logging::CollisionRecord& c : log.collisions) {
      if (c.frame_id != dropped) follower_->collision(c, 0);
    }
    follower_->finish();
    if (out != nullptr) *out = follower_.get();
    const fs::path written = dir_ / "copy.ply";
    deform::write_model(written.string(), setup.model);
    return deform::read_model(written.string());
  }

  std::unique_ptr<view::FrameFollower> follower_;
};

TEST_F(InjectedGap, IsDetectedAndTheCatchUpMakesTheCopyExact) {
  // The log stands in for the live channel, which carries every tick: it keeps them all here.
  const fs::path scene = press_scene("", /*log_every_tick=*/true);
  ASSERT_EQ(run_station(scene, 4.0), 0) << read_text(dir_ / "run.txt");
  const view::SessionLog log = view::read_session_log((dir_ / "sphere-press.lcmlog").string());
  const deform::PointModel station = deform::read_model((dir_ / "sphere-press.ply").string());
  std::set<std::int64_t> ids;
  for (const auto& c : log.collisions) ids.insert(c.frame_id);
  ASSERT_GE(ids.size(), 3u) << "the press must span several frames";
  const std::int64_t middle = *std::next(ids.begin(), static_cast<long>(ids.size() / 2));
  std::printf("[ view ] %zu collision frames, ids %lld..%lld, %zu ticks; dropping frame %lld\n", ids.size(),
              static_cast<long long>(*ids.begin()), static_cast<long long>(*ids.rbegin()), log.ticks.size(),
              static_cast<long long>(middle));

  view::FrameFollower* f = nullptr;
  EXPECT_TRUE(same_points(follow(scene, log, -1, false, &f), station)) << "the whole log must give the station's model";
  EXPECT_FALSE(f->diverged());
  EXPECT_EQ(f->gaps(), 0u);
  EXPECT_EQ(f->frames_applied(), ids.size());

  EXPECT_FALSE(same_points(follow(scene, log, middle, false, &f), station));
  EXPECT_EQ(f->gaps(), 1u);
  EXPECT_EQ(f->diverged_frames(), 1);
  EXPECT_EQ(f->frames_applied(), ids.size() - 1);

  EXPECT_TRUE(same_points(follow(scene, log, middle, true, &f), station));
  EXPECT_FALSE(f->diverged());
  EXPECT_EQ(f->gaps(), 1u);
  EXPECT_EQ(f->frames_caught_up(), 1u);
  EXPECT_EQ(f->frames_applied(), ids.size());
}

}  // namespace
}  // namespace sculpt::test
