// The station's tick with a scripted glove and a recording haptic sink: it deforms where the
// finger presses, allocates nothing from the first tick, and releases every force within one tick
// of the glove going silent.
#include "sculpt/rt/station.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <thread>

#include "sculpt/deform/generators.hpp"
#include "station_fixtures.hpp"
#include "support/allocation_counter.hpp"

namespace sculpt::rt {
namespace {

using namespace test_fixtures;

class RecordingSink final : public hal::HapticSink {
 public:
  explicit RecordingSink(std::vector<hal::HapticCommand>* log) : log_(log) {}
  void start() override {}
  void stop() override {}
  bool send(const hal::HapticCommand& c) noexcept override {
    if (log_->size() < log_->capacity()) log_->push_back(c);  // capacity reserved by the test
    return true;
  }
  std::uint64_t dropped() const noexcept override { return 0; }
  std::uint64_t delivered() const noexcept override { return log_->size(); }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override {
    return static_cast<std::uint64_t>(std::count_if(log_->begin(), log_->end(), [hand](const hal::HapticCommand& c) {
      return c.hand == hand && c.active_mask != 0;
    }));
  }
  const char* name() const noexcept override { return "recording"; }

 private:
  std::vector<hal::HapticCommand>* log_;
};

// The station's index answers nearest() on the deformed model as brute force does.
void expect_nearest_exact(Station& station, const deform::PointModel& model) {
  for (const deform::Vec3 q : {deform::Vec3{0, 0, 0.9}, deform::Vec3{0.1, 0.05, 1.1}, deform::Vec3{0, 0, 0.97}}) {
    double best = 1e9;
    for (std::size_t k = 0; k < model.size(); ++k) best = std::min(best, deform::norm(model.position(k) - q));
    EXPECT_DOUBLE_EQ(station.deformer().index().nearest(model, q, station.deformer().drift()).distance, best);
  }
}

TEST(Station, PressDeformsTheSphereAllocatesNothingAndReleasesWhenTheGloveGoesSilent) {
  deform::PointModel sphere = deform::make_sphere();
  const deform::PointModel before = sphere;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  std::vector<hal::HapticCommand> haptics;
  haptics.reserve(10000);
  Station station(sphere, press_settings(), std::move(glove), std::make_unique<RecordingSink>(&haptics));
  station.start();

  // The finger descends along +z onto the pole from 1.3 to 0.9 in 5 ms steps (one sample per
  // 5 ticks of a 1 kHz loop), then holds.
  std::int64_t now = 0;
  std::uint64_t collisions = 0;
  std::uint64_t colliding_frames = 0;
  double slowest_colliding_frame_ns = 0.0;
  // A tight budget (30 us per tick) keeps the auto region small: it may move only the points
  // that budget pays for, nearest first.
  constexpr std::int64_t kBudget = 30'000;
  auto step = [&](double z, bool feed) {
    for (int t = 0; t < 5; ++t) {
      now += kMs;
      if (feed && t == 0) g->feed({0.0, 0.0, z}, now, static_cast<std::uint64_t>(now / 1000));
      const TickReport& r = station.tick(now, kBudget);
      collisions += r.collisions;
      if (r.frame && r.collisions > 0) {
        ++colliding_frames;
        slowest_colliding_frame_ns = std::max(slowest_colliding_frame_ns, r.deform_ns);
      }
    }
  };
  // Counted from the very first tick: every buffer is sized when the station is built, so not
  // even the first contact, the first frame or the first haptic command may allocate.
  std::uint64_t allocations = 0;
  {
    test::AllocationCounter counter;
    for (int i = 0; i <= 20; ++i) step(1.3 - 0.02 * i, true);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0u) << "the tick allocated";
  EXPECT_GT(collisions, 0u);
  EXPECT_GT(station.totals().frames, 10u);
  // Every frame with a collision, and only those, timed as its tick reported it.
  const LatencyHistogram& frame_time = station.totals().collision_frame_time;
  EXPECT_GT(colliding_frames, 0u);
  EXPECT_LT(colliding_frames, station.totals().frames);  // the descent's first frames touch nothing
  EXPECT_EQ(frame_time.count(), colliding_frames);
  EXPECT_EQ(frame_time.max(), std::llround(slowest_colliding_frame_ns));
  // The pole was pushed in toward the finger's final depth.
  double lowest = 2.0;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    if (before.z[i] > 0.0f && std::abs(sphere.x[i]) < 0.05 && std::abs(sphere.y[i]) < 0.05)
      lowest = std::min(lowest, double(sphere.z[i]));
  }
  EXPECT_LT(lowest, 0.95);
  EXPECT_GT(lowest, 0.85);
  // The far side did not move much.
  std::size_t far = 0;
  for (std::size_t i = 0; i < sphere.size(); ++i)
    if (before.z[i] < -0.5f && sphere.z[i] != before.z[i]) ++far;
  EXPECT_EQ(far, 0u) << "the auto region should keep the far side untouched";
  EXPECT_GT(station.totals().max_region_points, 0u);
  EXPECT_LT(station.totals().max_region_points, sphere.size());
  ASSERT_FALSE(haptics.empty());
  bool felt = false;
  for (const hal::HapticCommand& c : haptics) felt |= (c.active_mask & 0b10) && c.force[1][2] > 0.0f;
  EXPECT_TRUE(felt) << "a press pushes the finger back out, along +z";

  // Silence: within one tick past the timeout every force is released.
  const std::size_t sent = haptics.size();
  const std::int64_t last_sample = now - 4 * kMs;
  while (now + kMs - last_sample <= 50 * kMs) {  // ticks up to an age of exactly the timeout
    now += kMs;
    EXPECT_NE(station.tick(now, kMs).glove, GloveState::kStale);
  }
  now += kMs;
  EXPECT_EQ(station.tick(now, kMs).glove, GloveState::kStale);
  ASSERT_GT(haptics.size(), sent);
  EXPECT_EQ(haptics.back().active_mask, 0);
  EXPECT_EQ(haptics.back().force[1][2], 0.0f);
  EXPECT_FALSE(station.fingers()[0].in_contact);
  EXPECT_EQ(station.totals().stale_events, 1u);

  // Data from before the silence never makes a force: the next sample starts a new stroke.
  const deform::PointModel held = sphere;
  g->feed({0.0, 0.0, 0.5}, now, static_cast<std::uint64_t>(now / 1000));
  now += kMs;
  const TickReport& r = station.tick(now, kMs);
  EXPECT_EQ(r.glove, GloveState::kLive);
  EXPECT_EQ(r.collisions, 0u);
  EXPECT_EQ(sphere.z, held.z);

  // The region's moved points are listed beside the tree, so its queries stay exact against
  // brute force on the deformed model with no rebuild (the station rebuilds once the list is
  // half full, or by the drift without a list: the next test).
  EXPECT_TRUE(station.deformer().index().moved_complete());
  EXPECT_GT(station.deformer().index().moved_count(), 0u);
  expect_nearest_exact(station, sphere);
}

// A global frame moves every point, which no list of moved points holds: the station then
// rebuilds the tree in the background once the points have drifted, and the queries stay
// exact throughout.
TEST(Station, AGlobalStrokeRebuildsTheIndexInTheBackgroundAndStaysExact) {
  deform::PointModel sphere = deform::make_sphere();
  StationSettings settings = press_settings();
  settings.region.kind = RegionPolicy::Kind::kGlobal;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  std::vector<hal::HapticCommand> haptics;
  haptics.reserve(10000);
  Station station(sphere, settings, std::move(glove), std::make_unique<RecordingSink>(&haptics));
  station.start();
  std::int64_t now = 0;
  for (int i = 0; i <= 20; ++i) {
    for (int k = 0; k < 5; ++k) {
      now += kMs;
      if (k == 0) g->feed({0.0, 0.0, 1.3 - 0.02 * i}, now, static_cast<std::uint64_t>(now / 1000));
      station.tick(now, kMs);
    }
  }
  EXPECT_GT(station.totals().frames, 10u);
  EXPECT_FALSE(station.deformer().index().moved_complete());
  // Give the worker up to 2 s of real time, ticking.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (station.totals().index_rebuilds == 0 && std::chrono::steady_clock::now() < give_up) {
    now += kMs;
    station.tick(now, kMs);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_GT(station.totals().index_rebuilds, 0u);
  expect_nearest_exact(station, sphere);
}

// Two hands, the right one goes silent: its finger is released within one tick past the
// timeout and cannot deform until it reports again, while the left one keeps sculpting.
// With the displacement loop's worker on the second core (deform threads = 2) and a model big
// enough that every frame is split: the tick still allocates nothing from the first tick (the
// worker was started when the station was built), and the sculpted model is byte for byte the
// one a single thread makes.
TEST(Station, TheSecondCoresWorkerAllocatesNothingAndChangesNoByte) {
  const deform::PointModel base = deform::make_sphere(40000);
  deform::PointModel models[2] = {base, base};
  std::uint64_t allocations[2] = {0, 0}, frames[2] = {0, 0};
  for (int t = 0; t < 2; ++t) {
    StationSettings settings = press_settings();
    settings.region.kind = RegionPolicy::Kind::kGlobal;  // every point: the pass is split
    settings.deform.threads = t + 1;
    auto glove = std::make_unique<FakeGlove>();
    FakeGlove* g = glove.get();
    std::vector<hal::HapticCommand> haptics;
    haptics.reserve(1000);
    Station station(models[t], settings, std::move(glove), std::make_unique<RecordingSink>(&haptics));
    station.start();
    std::int64_t now = 0;
    test::AllocationCounter counter;
    for (int i = 0; i <= 20; ++i) {
      for (int k = 0; k < 5; ++k) {
        now += kMs;
        if (k == 0) g->feed({0.0, 0.0, 1.3 - 0.02 * i}, now, static_cast<std::uint64_t>(now / 1000));
        station.tick(now, kMs);
      }
    }
    allocations[t] = counter.count();
    frames[t] = station.totals().frames;
  }
  EXPECT_EQ(allocations[1], 0u) << "the tick allocated with the worker";
  EXPECT_EQ(allocations[0], 0u);
  EXPECT_GT(frames[1], 10u);
  EXPECT_EQ(frames[0], frames[1]);
  EXPECT_EQ(std::memcmp(models[0].z.data(), models[1].z.data(), base.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(models[0].x.data(), models[1].x.data(), base.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(models[0].nz.data(), models[1].nz.data(), base.size() * sizeof(float)), 0);
  EXPECT_NE(std::memcmp(models[0].z.data(), base.z.data(), base.size() * sizeof(float)), 0);
}

TEST(Station, ASilentHandIsReleasedWhileTheOtherKeepsSculpting) {
  deform::PointModel sphere = deform::make_sphere();
  StationSettings s = press_settings();
  s.fingers = {{0, 1}, {1, 1}};
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  std::vector<hal::HapticCommand> haptics;
  haptics.reserve(10000);
  Station station(sphere, s, std::move(glove), std::make_unique<RecordingSink>(&haptics));
  station.start();
  std::int64_t now = 0;
  // Left finger presses down onto the north pole, right finger onto the south pole (from below).
  auto feed_both = [&](double depth, bool right) {
    g->feed({0.0, 0.0, 1.2 - depth}, now, static_cast<std::uint64_t>(now / 1000), 0);
    if (right) g->feed({0.0, 0.0, -1.2 + depth}, now, static_cast<std::uint64_t>(now / 1000), 1);
  };
  for (int i = 0; i < 12; ++i) {
    now += 5 * kMs;
    feed_both(0.03 * i, true);
    station.tick(now, kMs);
  }
  ASSERT_TRUE(station.fingers()[0].in_contact);
  ASSERT_TRUE(station.fingers()[1].in_contact);
  const std::int64_t right_last = now;
  // Only the left hand reports from here on.
  const std::uint64_t stale_before = station.totals().stale_events;
  bool released_at_timeout = false;
  for (int t = 1; t <= 80; ++t) {
    now += kMs;
    if (t % 5 == 0) feed_both(0.36 + 0.002 * t, false);
    const TickReport& r = station.tick(now, kMs);
    const bool past = now - right_last > 50 * kMs;
    if (!past) {
      EXPECT_TRUE(station.fingers()[1].in_contact || r.glove == GloveState::kLive) << "tick " << t;
      continue;
    }
    // Within one tick past the timeout: the right finger is out of contact with zero force.
    EXPECT_FALSE(station.fingers()[1].in_contact) << "tick " << t;
    EXPECT_EQ(station.fingers()[1].haptic_force.z, 0.0) << "tick " << t;
    released_at_timeout = true;
  }
  EXPECT_TRUE(released_at_timeout);
  EXPECT_EQ(station.totals().stale_events, stale_before + 1);
  // A zero command went to the right hand.
  bool zero_right = false;
  for (const hal::HapticCommand& c : haptics) zero_right |= c.hand == 1 && c.active_mask == 0;
  EXPECT_TRUE(zero_right);
  // The left finger kept pressing and deforming after the right one went silent.
  EXPECT_TRUE(station.fingers()[0].in_contact);
  const deform::PointModel held = sphere;
  const std::uint64_t right_collisions = station.fingers()[1].collisions;
  now += 5 * kMs;
  feed_both(0.6, false);
  const TickReport& r = station.tick(now, kMs);
  EXPECT_NE(sphere.z, held.z) << "the live hand still sculpts";
  EXPECT_EQ(r.collisions, 1u) << "only the live hand's finger presses";
  EXPECT_EQ(station.fingers()[1].collisions, right_collisions) << "the silent hand cannot deform";
}

// A press held still: a command every loop tick while in contact, its `tick` the loop's tick,
// never above max_force, rising no faster than the slew limit; one zero command on letting go,
// then heartbeats at most 100 ms apart.
TEST(Station, HapticsEveryTickBoundedSlewLimitedAndReleasedInOneTick) {
  deform::PointModel sphere = deform::make_sphere();
  StationSettings s = press_settings();
  s.haptic.max_force = 4.0;
  s.haptic.max_force_rate = 200.0;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  std::vector<hal::HapticCommand> haptics;
  haptics.reserve(20000);
  Station station(sphere, s, std::move(glove), std::make_unique<RecordingSink>(&haptics));
  station.start();
  std::int64_t now = 0;
  for (int i = 0; i <= 14; ++i) {  // down onto the pole and 0.08 in, a sample per 5 ticks
    for (int t = 0; t < 5; ++t) {
      now += kMs;
      if (t == 0) g->feed({0.0, 0.0, 1.2 - 0.02 * i}, now, static_cast<std::uint64_t>(now / 1000));
      station.tick(now, kMs);
    }
  }
  ASSERT_TRUE(station.fingers()[0].in_contact);
  // Hold for one second at 1 kHz, the glove still reporting the same position.
  const std::size_t hold_begin = haptics.size();
  for (int t = 0; t < 1000; ++t) {
    now += kMs;
    if (t % 5 == 0) g->feed({0.0, 0.0, 1.2 - 0.02 * 14}, now, static_cast<std::uint64_t>(now / 1000));
    station.tick(now, kMs);
  }
  ASSERT_GE(haptics.size() - hold_begin, 1000u) << "a command every tick of the hold";
  for (std::size_t k = hold_begin; k < haptics.size(); ++k) {
    const hal::HapticCommand& c = haptics[k];
    EXPECT_TRUE(c.active_mask & 0b10) << "command " << k;
    const auto& f = c.force[1];
    const double n = std::sqrt(double(f[0]) * f[0] + double(f[1]) * f[1] + double(f[2]) * f[2]);
    EXPECT_LE(n, 4.0 + 1e-6);
    if (k > hold_begin) {
      EXPECT_EQ(c.tick, haptics[k - 1].tick + 1) << "loop ticks, one apart";
    }
  }
  EXPECT_GT(haptics.back().force[1][2], 0.0f) << "held: the surface still pushes the finger out";
  double rise = 0.0, previous = 0.0;
  for (const hal::HapticCommand& c : haptics) {
    const auto& f = c.force[1];
    const double n = std::sqrt(double(f[0]) * f[0] + double(f[1]) * f[1] + double(f[2]) * f[2]);
    rise = std::max(rise, n - previous);
    previous = n;
  }
  EXPECT_LE(rise, 0.2 + 1e-6) << "200 N/s at 1 kHz";
  // Lift off: the frame classes the finger free, and the same tick sends zero.
  now += kMs;
  g->feed({0.0, 0.0, 1.3}, now, static_cast<std::uint64_t>(now / 1000));
  const std::size_t before_lift = haptics.size();
  station.tick(now, kMs);
  ASSERT_EQ(haptics.size(), before_lift + 1);
  EXPECT_EQ(haptics.back().active_mask, 0);
  EXPECT_EQ(haptics.back().force[1][2], 0.0f);
  // Out of contact: heartbeats only, at most 100 ms apart.
  const std::size_t idle_begin = haptics.size();
  for (int t = 0; t < 500; ++t) {
    now += kMs;
    if (t % 5 == 0) g->feed({0.0, 0.0, 1.3}, now, static_cast<std::uint64_t>(now / 1000));
    station.tick(now, kMs);
  }
  EXPECT_GE(haptics.size() - idle_begin, 4u);
  EXPECT_LE(haptics.size() - idle_begin, 6u);
}

// A sink whose queue is full every third time it is offered a command.
class SometimesFullSink final : public hal::HapticSink {
 public:
  void start() override {}
  void stop() override {}
  bool send(const hal::HapticCommand& c) noexcept override {
    const bool taken = ++offered_ % 3 != 0;
    if (taken && c.active_mask != 0) {
      ++taken_in_contact;
      if (c.hand < hal::kHands) ++taken_in_contact_by_hand_[c.hand];
    }
    return taken;
  }
  std::uint64_t dropped() const noexcept override { return offered_ / 3; }
  std::uint64_t delivered() const noexcept override { return offered_ - offered_ / 3; }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override {
    return hand < hal::kHands ? taken_in_contact_by_hand_[hand] : 0;
  }
  const char* name() const noexcept override { return "sometimes full"; }

  std::uint64_t taken_in_contact = 0;

 private:
  std::uint64_t offered_ = 0;
  std::array<std::uint64_t, hal::kHands> taken_in_contact_by_hand_{};
};

TEST(Station, CountsEachHandsTicksInContactAndTheCommandsItsSinkTookInThem) {
  deform::PointModel sphere = deform::make_sphere();
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  auto sink = std::make_unique<SometimesFullSink>();
  const SometimesFullSink* counted = sink.get();
  Station station(sphere, press_settings(), std::move(glove), std::move(sink));
  station.start();
  // Down onto the pole, a hold, and off again; the test counts the ticks in contact itself.
  std::int64_t now = 0;
  std::uint64_t ticks_in_contact = 0;
  for (int i = 0; i <= 60; ++i) {
    const double z = i <= 14 ? 1.2 - 0.02 * i : (i < 50 ? 1.2 - 0.02 * 14 : 1.3);
    for (int t = 0; t < 5; ++t) {
      now += kMs;
      if (t == 0) g->feed({0.0, 0.0, z}, now, static_cast<std::uint64_t>(now / 1000));
      station.tick(now, kMs);
      ticks_in_contact += station.fingers()[0].in_contact ? 1 : 0;
    }
  }
  station.stop();
  ASSERT_GT(ticks_in_contact, 100u);
  const StationTotals& totals = station.totals();
  EXPECT_EQ(totals.contact_ticks[0], ticks_in_contact);
  EXPECT_EQ(totals.contact_commands[0], counted->taken_in_contact);
  EXPECT_LT(totals.contact_commands[0], totals.contact_ticks[0]) << "the refusals must show";
  EXPECT_EQ(totals.contact_ticks[1], 0u);
  EXPECT_EQ(totals.contact_commands[1], 0u);
}

// A glove frame with a valid CRC may carry inf or NaN (a sim glove with a jitter of 1e308 made
// them). Each such sample is dropped and counted, with the filter on as at the station: the
// filter holds its last output for a non-finite value, and that output was the origin, inside
// the sphere, which once made a collision from nothing. Between them a good stroke still presses.
// Finite joint angles can still sum to inf in the hand model; that fingertip is dropped too.
TEST(Station, ANonFiniteGloveSampleOrFingertipIsDroppedAndCountedNeverFilteredIntoAPosition) {
  deform::PointModel sphere = deform::make_sphere();
  const deform::PointModel before = sphere;
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  StationSettings settings = press_settings();
  settings.filter_enabled = true;
  settings.filter.min_cutoff = 50.0;  // follows the press within a few samples
  Station station(sphere, settings, std::move(glove), nullptr);
  station.start();
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::int64_t now = 0;
  std::uint64_t collisions = 0;
  const auto sample = [&](const deform::Vec3& tip) {
    g->feed(tip, now + kMs, static_cast<std::uint64_t>((now + kMs) / 1000));
    for (int t = 0; t < 5; ++t) {  // one sample per five ticks of a 1 kHz loop
      now += kMs;
      collisions += station.tick(now, kMs).collisions;
    }
  };
  sample({-inf, -inf, inf});  // the first sample: the filter has no output yet
  sample({inf, inf, -inf});
  sample({nan, 0.0, 1.3});
  EXPECT_EQ(station.totals().out_of_range, 3u);
  EXPECT_EQ(station.tick(now + kMs, kMs).glove, GloveState::kWaiting);  // none of them made the hand live
  EXPECT_EQ(collisions, 0u);
  EXPECT_EQ(sphere.x, before.x);
  EXPECT_EQ(sphere.y, before.y);
  EXPECT_EQ(sphere.z, before.z);
  now += kMs;
  for (int i = 0; i <= 20; ++i) sample({0.0, 0.0, 1.3 - 0.02 * i});  // a press down to 0.9
  EXPECT_GT(collisions, 0u);
  EXPECT_EQ(station.totals().out_of_range, 3u);
  const deform::PointModel pressed = sphere;
  const std::uint64_t pressing = collisions;
  sample({0.0, inf, 0.9});  // mid-press: held, not taken for the last good position
  sample({0.0, 0.0, nan});
  EXPECT_EQ(station.totals().out_of_range, 5u);
  EXPECT_EQ(collisions, pressing);
  EXPECT_EQ(sphere.z, pressed.z);
  // Angles of 3e38 are finite and pass intake; their sum along the finger is inf, its cosine NaN.
  hal::GloveSample bent;
  bent.kind = hal::SampleKind::kAngles;
  for (auto& finger : bent.angles) finger = {3e38f, 3e38f, 3e38f, 3e38f};
  ASSERT_TRUE(hal::all_finite(bent));
  for (int t = 0; t < 5; ++t) {
    bent.device_time_us = static_cast<std::uint64_t>((now + kMs) / 1000);
    bent.receive_time_ns = now + kMs;
    g->feed_sample(bent);
    now += kMs;
    collisions += station.tick(now, kMs).collisions;
  }
  EXPECT_EQ(station.totals().out_of_range, 10u);
  EXPECT_EQ(collisions, pressing);
  EXPECT_EQ(sphere.z, pressed.z);
  for (std::size_t i = 0; i < sphere.size(); ++i) ASSERT_TRUE(deform::is_finite(sphere.position(i))) << i;
}

// The loop acts on a hand's newest sample of those one tick takes; the older ones are counted
// as superseded (a glove faster than the loop), so a session's summary says how many.
TEST(Station, OfOneTicksSamplesTheNewestOfEachHandActsAndTheRestAreCounted) {
  deform::PointModel sphere = deform::make_sphere();
  auto glove = std::make_unique<FakeGlove>();
  FakeGlove* g = glove.get();
  StationSettings settings = press_settings();
  settings.fingers = {{0, 1}, {1, 1}};
  Station station(sphere, settings, std::move(glove), nullptr);
  station.start();
  g->feed({0.0, 0.0, 1.5}, kMs / 4, 250);
  g->feed({0.0, 0.0, 1.7}, kMs / 2, 500, /*hand=*/1);
  g->feed({0.0, 0.0, 1.4}, 3 * kMs / 4, 750);  // hand 0 again: this one acts
  EXPECT_EQ(station.tick(kMs, kMs).samples, 3u);
  EXPECT_EQ(station.totals().samples, 3u);
  EXPECT_EQ(station.totals().superseded_samples, 1u);
  EXPECT_EQ(station.fingers()[0].raw.z, 1.4f);
  EXPECT_EQ(station.fingers()[1].raw.z, 1.7f);
  g->feed({0.0, 0.0, 1.3}, 5 * kMs / 4, 1250);  // one sample a tick: nothing superseded
  station.tick(2 * kMs, kMs);
  EXPECT_EQ(station.totals().superseded_samples, 1u);
  EXPECT_EQ(station.fingers()[0].raw.z, 1.3f);
}

TEST(Station, RejectsBadFingerLists) {
  deform::PointModel sphere = deform::make_sphere();
  StationSettings s = press_settings();
  s.fingers = {};
  EXPECT_THROW(Station(sphere, s, std::make_unique<FakeGlove>(), nullptr), std::invalid_argument);
  s.fingers = {{0, 1}, {0, 1}};
  EXPECT_THROW(Station(sphere, s, std::make_unique<FakeGlove>(), nullptr), std::invalid_argument);
  s.fingers = {{2, 1}};
  EXPECT_THROW(Station(sphere, s, std::make_unique<FakeGlove>(), nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::rt
