// The station fed over LCM in one process (memq://): the sim script published as
// glove_sample_t, received by the LCM glove source, pressed into the sphere.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "sculpt/deform/generators.hpp"
#include "sculpt/hal/backend_factory.hpp"
#include "sculpt/hal/sim_script.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/rt/fixed_rate_loop.hpp"
#include "sculpt/rt/scene.hpp"
#include "sculpt/rt/station.hpp"

namespace sculpt::rt {
namespace {

TEST(LcmMemqStation, ScriptedPressArrivesOverMemqAndDeformsTheSphere) {
  const Scene scene = load_scene(std::string(SCULPT_SOURCE_DIR) + "/scenes/sphere-press.toml");
  lcm::LCM bus("memq://");
  ASSERT_TRUE(bus.good());
  hal::LcmConfig config;
  auto glove = hal::make_lcm_glove_source(bus, config, 256);
  deform::PointModel sphere = deform::make_sphere();
  const deform::PointModel before = sphere;
  StationSettings settings;
  settings.fingers = {{0, 1}};
  settings.delta_s = 0.06;
  settings.deform.contact.bc_radius = 0.06;
  settings.deform.contact.min_source_distance = 0.015;
  settings.deform.contact.guard_distance = 0.09;
  settings.region.kind = RegionPolicy::Kind::kGlobal;
  Station station(sphere, settings, std::move(glove), nullptr);
  station.start();

  hal::SimScript script(scene.glove.config.sim);
  hal::GloveSample sample;
  const std::int64_t start = monotonic_now_ns();
  std::uint64_t published = 0;
  while (script.next(sample) && sample.device_time_us < 2'000'000) {  // the approach and press
    sleep_until_ns(start + static_cast<std::int64_t>(sample.device_time_us) * 1000);
    sculpt_lcm::glove_sample_t message;
    hal::to_lcm(sample, base::wall_time_us(), message);
    ASSERT_EQ(bus.publish(logging::kGloveChannel, &message), 0);
    ++published;
    // Tick until the source has delivered it (bounded: memq hands over within the I/O
    // thread's next handle call).
    const std::uint64_t want = station.totals().samples + 1;
    const std::int64_t give_up = monotonic_now_ns() + 500'000'000;
    while (station.totals().samples < want && monotonic_now_ns() < give_up) {
      station.tick(monotonic_now_ns(), 1'000'000);
      sleep_until_ns(monotonic_now_ns() + 200'000);
    }
  }
  station.stop();
  EXPECT_EQ(station.totals().samples, published);
  EXPECT_GT(station.totals().collisions, 0u);
  EXPECT_EQ(station.glove_counters().framing_errors, 0u);
  double top = -1.0;
  for (std::size_t i = 0; i < sphere.size(); ++i)
    if (before.z[i] > 0.99f) top = std::max(top, double(sphere.z[i]));
  EXPECT_LT(top, 0.99);
}

}  // namespace
}  // namespace sculpt::rt
