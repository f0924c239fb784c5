// The region's kept balls against a brute-force pass over every point at its current position:
// through strokes whose points move under the fingers, a query answered from a kept ball must
// be the very set a fresh query finds, and a ball must stop being used once the fingers or the
// points may have left it.
#include "sculpt/deform/ball_cache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sphere_settings.hpp"

namespace sculpt::deform {
namespace {

// Every point within radius of c, by its own squared distance in double from the float
// coordinates (the comparison the index documents), ascending.
std::vector<std::uint32_t> brute_force(const PointModel& model, const Vec3& c, double radius) {
  std::vector<std::uint32_t> inside;
  for (std::uint32_t i = 0; i < model.size(); ++i) {
    const double dx = static_cast<double>(model.x[i]) - c.x;
    const double dy = static_cast<double>(model.y[i]) - c.y;
    const double dz = static_cast<double>(model.z[i]) - c.z;
    if (dx * dx + dy * dy + dz * dz <= radius * radius) inside.push_back(i);
  }
  return inside;
}

std::vector<std::uint32_t> sorted(std::vector<std::uint32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// Sinks the points near c towards the sphere's centre by up to `depth`, as a press does, and
// returns how far the farthest moved.
double press(PointModel& model, const Vec3& c, double depth, double reach) {
  double farthest = 0.0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const Vec3 p = model.position(i);
    const double closeness = std::max(0.0, 1.0 - norm(p - c) / reach);
    if (closeness == 0.0) continue;
    model.set_position(i, p - normalized(p) * (depth * closeness));
    farthest = std::max(farthest, norm(model.position(i) - p));
  }
  return farthest;
}

TEST(BallCache, AStrokesBallsAreTheBruteForceSetsWhileTheFingersSlideAndThePointsSink) {
  PointModel model = make_sphere(20000);
  const PointIndex index(model);  // the snapshot the drift is counted from
  BallCache balls(model.size(), BallCache::kRegionMargin, false);
  std::vector<std::uint32_t> out;
  out.reserve(model.size());
  const double radius = 0.2;
  double drift = 0.0;
  for (int frame = 0; frame < 60; ++frame) {
    // Three fingers: two slide slowly side by side (their balls overlap), the third fast enough
    // to leave a kept ball every other frame; all press a little deeper each frame.
    const double a = 0.004 * frame, b = 0.03 * frame;
    const std::vector<Vec3> contacts = {{std::cos(a), std::sin(a), 0.0},
                                        {std::cos(a + 0.05), std::sin(a + 0.05), 0.02},
                                        {0.0, std::sin(b), -std::cos(b)}};
    for (const Vec3& c : contacts) {
      balls.within_radius(model, index, drift, c, radius, out);
      SCOPED_TRACE(::testing::Message() << "frame " << frame);
      ASSERT_EQ(sorted(out), brute_force(model, c, radius));
    }
    balls.end_frame();
    double moved = 0.0;
    for (const Vec3& c : contacts) moved = std::max(moved, press(model, c, 0.002, 0.15));
    balls.add_move(moved);
    drift += moved * 3.0;  // the index's bound may be loose; the balls' must hold
  }
  // Every way was met: the slow fingers kept their balls, the fast one needed new ones, and the
  // first frame, a press, asked plainly.
  EXPECT_GT(balls.hits(), 90u);
  EXPECT_GT(balls.wider(), 20u);
  EXPECT_EQ(balls.plain(), 3u);
}

// A 5,000-point sphere, its index and a cache, asked for balls of 0.3 near its pole.
class BallCacheOnASphere : public ::testing::Test {
 protected:
  BallCacheOnASphere() { out_.reserve(model_.size()); }
  PointModel model_ = make_sphere(5000);
  const PointIndex index_{model_};
  BallCache balls_{model_.size(), BallCache::kRegionMargin, false};
  std::vector<std::uint32_t> out_;
  const double radius_ = 0.3;
  const double margin_ = radius_ * BallCache::kRegionMargin;
  const Vec3 c_{0.0, 0.0, 1.0};
};

TEST_F(BallCacheOnASphere, ABallIsKeptInAStrokeAndLeftOnceTheFingerOrThePointsMayHaveLeftIt) {
  const auto frame = [&](const Vec3& at) {
    balls_.within_radius(model_, index_, 0.0, at, radius_, out_);
    EXPECT_EQ(sorted(out_), brute_force(model_, at, radius_));
    balls_.end_frame();
  };
  // A finger coming down: a plain query, nothing kept (a single press pays nothing more).
  frame(c_);
  EXPECT_EQ(balls_.plain(), 1u);
  EXPECT_EQ(balls_.wider(), 0u);
  // The next frame near it: a stroke, so a wider ball is found and kept.
  const Vec3 c1 = c_ + Vec3{0.1 * margin_, 0.0, 0.0};
  frame(c1);
  EXPECT_EQ(balls_.wider(), 1u);
  // A finger that moved half the margin since is still covered.
  frame(c1 + Vec3{0.5 * margin_, 0.0, 0.0});
  EXPECT_EQ(balls_.hits(), 1u);
  // Points told to have moved half the margin leave a finger that moved half of it uncovered.
  balls_.add_move(0.5 * margin_);
  frame(c1 + Vec3{0.0, 0.51 * margin_, 0.0});
  EXPECT_EQ(balls_.hits(), 1u);
  EXPECT_EQ(balls_.wider(), 2u);
  // Back where the first ball was found, moved half the margin: covered.
  frame(c1);
  EXPECT_EQ(balls_.hits(), 2u);
  // A move that is not a number forgets every ball and every finger: a press again.
  balls_.add_move(std::numeric_limits<double>::quiet_NaN());
  frame(c1);
  EXPECT_EQ(balls_.plain(), 2u);
  frame(c1);
  EXPECT_EQ(balls_.wider(), 3u);
  frame(c1);
  EXPECT_EQ(balls_.hits(), 3u);
  // And so does forget().
  balls_.forget();
  frame(c1);
  EXPECT_EQ(balls_.plain(), 3u);
  EXPECT_EQ(balls_.hits(), 3u);
  // A finger jumping farther than the margin every frame never pays for a wider ball.
  for (int k = 1; k <= 6; ++k) frame(c1 + Vec3{0.0, 1.5 * margin_ * k, 0.0});
  EXPECT_EQ(balls_.plain(), 9u);
  EXPECT_EQ(balls_.wider(), 3u);
}

TEST_F(BallCacheOnASphere, PointsThatMovedIntoAKeptBallAreFoundWhereTheyAreNow) {
  for (int k = 0; k < 2; ++k) {
    balls_.within_radius(model_, index_, 0.0, c_, radius_, out_);
    balls_.end_frame();
  }
  ASSERT_EQ(balls_.wider(), 1u);
  // A press sinks the points under the finger by about half the margin, and the finger follows
  // them down: the points that came within its ball are found in the kept one.
  const double moved = press(model_, c_, 0.5 * margin_, 2.0 * radius_);
  ASSERT_GT(moved, 0.4 * margin_);
  balls_.add_move(moved);
  const Vec3 lower = c_ - Vec3{0.0, 0.0, 0.4 * margin_};
  const std::vector<std::uint32_t> now = brute_force(model_, lower, radius_);
  ASSERT_NE(now, brute_force(make_sphere(5000), lower, radius_));  // the press changed the answer
  balls_.within_radius(model_, index_, moved, lower, radius_, out_);
  EXPECT_EQ(balls_.hits(), 1u);
  EXPECT_EQ(sorted(out_), now);
}

TEST(BallCache, MoreBallsThanItKeepsOrMoreCandidatesThanItHoldsStillAnswerExactly) {
  const PointModel model = make_sphere(8000);
  const PointIndex index(model);
  std::vector<std::uint32_t> out;
  out.reserve(model.size());
  // Forty fingers in one frame, more balls than it keeps (32), asked three times.
  BallCache balls(model.size(), BallCache::kRegionMargin, false);
  std::vector<Vec3> contacts;
  for (int k = 0; k < 40; ++k) contacts.push_back(model.position(static_cast<std::size_t>(k) * 197));
  for (int round = 0; round < 3; ++round) {
    for (const Vec3& c : contacts) {
      balls.within_radius(model, index, 0.0, c, 0.25, out);
      ASSERT_EQ(sorted(out), brute_force(model, c, 0.25));
    }
    balls.end_frame();
  }
  EXPECT_GT(balls.hits(), 0u);
  // Balls holding most of the model: the pool (a model's worth) cannot keep a second one, and
  // the answers are exact all the same.
  BallCache crowded(model.size(), BallCache::kRegionMargin, false);
  for (int round = 0; round < 3; ++round) {
    for (const Vec3& c : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}}) {
      crowded.within_radius(model, index, 0.0, c, 1.5, out);
      ASSERT_EQ(sorted(out), brute_force(model, c, 1.5));
    }
    crowded.end_frame();
  }
  // A non-finite finger finds nothing and keeps nothing.
  crowded.within_radius(model, index, 0.0, Vec3{std::nan(""), 0.0, 0.0}, 0.25, out);
  EXPECT_TRUE(out.empty());
}

// The nearest point by brute force: the smallest squared distance, ties to the smallest index.
std::uint32_t brute_nearest(const PointModel& model, const Vec3& q) {
  std::uint32_t best = 0;
  double best_squared = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = 0; i < model.size(); ++i) {
    const double dx = static_cast<double>(model.x[i]) - q.x;
    const double dy = static_cast<double>(model.y[i]) - q.y;
    const double dz = static_cast<double>(model.z[i]) - q.z;
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < best_squared) {
      best_squared = d2;
      best = i;
    }
  }
  return best;
}

// A probe's balls (ascending, the wider margin) through a stroke that presses the points under
// it: locate() with them reads the same nearest point, the same neighbours in the same order
// and so the same side to the bit as locate() on the index alone, and the nearest point is the
// brute-force one, ties included (probes at midpoints of two points).
TEST(BallCache, ProbeBallsLocateAsTheIndexAloneDoesThroughAStroke) {
  PointModel model = make_sphere(20000);
  const PointIndex index(model);
  BallCache balls(model.size(), BallCache::kProbeMargin, /*ascending=*/true);
  ContactSettings settings;
  settings.bc_radius = 0.05;
  const double h = side_smoothing(model, index, settings.bc_radius);
  std::vector<std::uint32_t> with_balls, alone;
  with_balls.reserve(model.size());
  alone.reserve(model.size());
  std::uint32_t hint = PointIndex::kNoPoint;
  double drift = 0.0;
  int ties = 0;
  for (int frame = 0; frame < 80; ++frame) {
    const double a = 0.002 * frame;
    const Vec3 on_surface{std::sin(a), 0.0, std::cos(a)};
    // In and out of the surface by a few h; every fifth frame, between two points.
    Vec3 probe = on_surface * (1.0 + 0.6 * h * std::sin(0.4 * frame));
    if (frame % 5 == 4 && hint != PointIndex::kNoPoint) {
      // The hint's own nearest neighbour: at their midpoint the two tie, unless a third point
      // is nearer still.
      std::uint32_t other = hint == 0 ? 1 : 0;
      for (std::uint32_t j = 0; j < model.size(); ++j) {
        if (j != hint && squared_norm(model.position(j) - model.position(hint)) <
                             squared_norm(model.position(other) - model.position(hint))) {
          other = j;
        }
      }
      probe = (model.position(hint) + model.position(other)) * 0.5;
      const double to_hint = squared_norm(model.position(hint) - probe);
      if (to_hint == squared_norm(model.position(other) - probe) &&
          brute_nearest(model, probe) == std::min(hint, other) && other < hint) {
        ++ties;  // a tie the smaller index must win, against the hint
      }
    }
    SCOPED_TRACE(::testing::Message() << "frame " << frame);
    const SurfaceSide s = locate(model, index, drift, probe, settings, h, with_balls, hint, &balls);
    const SurfaceSide t = locate(model, index, drift, probe, settings, h, alone, hint);
    ASSERT_EQ(s.nearest, brute_nearest(model, probe));
    EXPECT_EQ(s.nearest, t.nearest);
    EXPECT_EQ(s.distance, t.distance);
    EXPECT_EQ(s.plane_side, t.plane_side);
    EXPECT_EQ(s.surface_side, t.surface_side);
    EXPECT_EQ(s.side, t.side);
    EXPECT_EQ(with_balls, alone);
    hint = s.nearest;
    balls.end_frame();
    const double moved = press(model, on_surface, 0.05 * h, 6.0 * h);
    balls.add_move(moved);
    drift += moved;
  }
  EXPECT_GE(ties, 3);
  EXPECT_GT(balls.hits(), 100u);  // nearest and the side's ball, most frames (138)
  EXPECT_GT(balls.wider(), 3u);
}

// The balls change nothing a frame computes: three fingers glide over a sphere, pressing deeper
// (region and probe balls kept), beside the same stroke on a deformer whose index is rebuilt
// before every frame, which forgets every ball, so that all its queries go to the tree. Every
// frame leaves both models equal to the bit.
TEST(BallCache, AStrokeWithKeptBallsMovesEveryPointAsOneWithoutThem) {
  const PointModel original = make_sphere(20000);
  PointModel kept = original, fresh = original;
  const DeformSettings settings = frames::sphere_settings(0.05, 0.01, 0.4);
  Deformer with_balls(kept, settings), without(fresh, settings);
  std::vector<ProbeMotion> motions(3);
  std::vector<Vec3> last(3);
  for (std::size_t f = 0; f < 3; ++f) {
    const double a = 0.8 * static_cast<double>(f);
    last[f] = Vec3{0.3 * std::cos(a), 0.3 * std::sin(a), 1.0} * 1.02;
  }
  std::size_t pressed = 0;
  for (int frame = 0; frame < 40; ++frame) {
    for (std::size_t f = 0; f < 3; ++f) {
      const double a = 0.8 * static_cast<double>(f) + 0.004 * frame;
      const Vec3 target = normalized(Vec3{0.3 * std::cos(a), 0.3 * std::sin(a), 1.0}) * (0.99 - 0.0005 * frame);
      motions[f] = ProbeMotion{last[f], target, std::nullopt};
    }
    without.rebuild_index();
    const FrameReport& r = with_balls.deform(motions);
    const std::size_t collisions = r.collisions;
    const FrameReport& s = without.deform(motions);
    SCOPED_TRACE(::testing::Message() << "frame " << frame);
    EXPECT_EQ(collisions, s.collisions);
    pressed += collisions;
    ASSERT_EQ(kept.x, fresh.x);
    ASSERT_EQ(kept.y, fresh.y);
    ASSERT_EQ(kept.z, fresh.z);
    ASSERT_EQ(kept.nz, fresh.nz);
    for (std::size_t f = 0; f < 3; ++f) last[f] = r.contacts[f].probe_after;
  }
  EXPECT_GT(pressed, 100u);                      // most fingers press most frames (every one, 120, when written)
  EXPECT_GT(with_balls.kept_ball_hits(), 500u);  // 1,340 when written
  EXPECT_EQ(without.kept_ball_hits(), 0u);
}

}  // namespace
}  // namespace sculpt::deform
