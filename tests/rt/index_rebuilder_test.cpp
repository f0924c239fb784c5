// The background k-d tree rebuild: installs an exact index, and can be destroyed at any moment
// (a destructor racing a build once overwrote the quit request and hung the join).
#include "sculpt/rt/index_rebuilder.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "sculpt/deform/generators.hpp"

namespace sculpt::rt {
namespace {

TEST(IndexRebuilder, InstallsAnIndexThatIsExactForTheMovedModel) {
  deform::PointModel sphere = deform::make_sphere();
  deform::DeformSettings settings;
  settings.contact.bc_radius = 0.08;
  deform::Deformer deformer(sphere, settings);
  const deform::ProbeMotion push{{0, 0, 1.1}, {0, 0, 0.9}, std::nullopt};
  deformer.deform({&push, 1});
  const double drift = deformer.drift();
  ASSERT_GT(drift, 0.0);
  IndexRebuilder rebuilder(sphere.size());
  ASSERT_TRUE(rebuilder.request(sphere, drift));
  EXPECT_FALSE(rebuilder.request(sphere, drift)) << "one rebuild at a time";
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!rebuilder.install(deformer) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(rebuilder.installed(), 1u);
  EXPECT_EQ(deformer.drift(), 0.0);  // the new snapshot is the current model
  for (const deform::Vec3 q : {deform::Vec3{0, 0, 0.85}, deform::Vec3{0.3, -0.2, 1.2}}) {
    double best = 1e9;
    for (std::size_t i = 0; i < sphere.size(); ++i) best = std::min(best, deform::norm(sphere.position(i) - q));
    EXPECT_DOUBLE_EQ(deformer.index().nearest(sphere, q, deformer.drift()).distance, best);
  }
}

TEST(IndexRebuilder, DestructionDuringABuildNeverHangs) {
  const deform::PointModel sphere = deform::make_sphere(20000);
  int requested = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 50; ++i) {
    IndexRebuilder rebuilder(sphere.size(), sphere.size());  // the whole snapshot in request()
    requested += rebuilder.request(sphere, 0.0);
    if (i % 2) std::this_thread::sleep_for(std::chrono::microseconds(100 * i));
  }  // each destructor joins its worker; a hang is caught by ctest's 300 s timeout
  EXPECT_EQ(requested, 50);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}

TEST(IndexRebuilder, ASnapshotSpreadOverTicksWhileTheModelMovesStillGivesAnExactIndex) {
  // 40,000 points copied 4,096 a tick: ten ticks, during which the finger keeps pressing, so
  // the snapshot holds points from different frames. The installed index must still be exact:
  // the drift counted from the request bounds how far any point moved since its copy.
  deform::PointModel sphere = deform::make_sphere(40000);
  deform::DeformSettings settings;
  settings.contact.bc_radius = 0.03;
  settings.contact.min_source_distance = 0.005;
  deform::Deformer deformer(sphere, settings);
  IndexRebuilder rebuilder(sphere.size(), 4096);
  const std::size_t ticks_to_copy = (sphere.size() + 4095) / 4096;
  double z = 1.02;
  auto press = [&] {
    const deform::ProbeMotion push{{0, 0, z}, {0, 0, z - 0.004}, std::nullopt};
    z -= 0.004;
    deformer.deform({&push, 1});
  };
  for (int i = 0; i < 8; ++i) press();
  ASSERT_GT(deformer.drift(), 0.0);
  ASSERT_TRUE(rebuilder.request(sphere, deformer.drift()));
  std::size_t ticks = 1;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!rebuilder.install(deformer) && std::chrono::steady_clock::now() < give_up) {
    press();  // the model moves between the chunks
    rebuilder.advance(sphere);
    ++ticks;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(rebuilder.installed(), 1u);
  EXPECT_GE(ticks, ticks_to_copy) << "the copy must be spread over the ticks";
  EXPECT_GT(deformer.drift(), 0.0) << "the model should have moved while it was copied";
  for (int q = 0; q < 200; ++q) {
    const double t = 0.1 * q;
    const deform::Vec3 p{0.3 * std::cos(t) * (q % 7) / 7.0, 0.3 * std::sin(t) * (q % 5) / 5.0, 0.8 + 0.002 * q};
    double best = 1e9;
    for (std::size_t i = 0; i < sphere.size(); ++i) best = std::min(best, deform::norm(sphere.position(i) - p));
    ASSERT_DOUBLE_EQ(deformer.index().nearest(sphere, p, deformer.drift()).distance, best) << "query " << q;
  }
}

}  // namespace
}  // namespace sculpt::rt
