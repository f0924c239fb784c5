#include "sculpt/rt/region_sizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

namespace sculpt::rt {
namespace {

// A station's frames as a cost model, the sizer's independent truth: a ball of radius r on a
// surface holds density * r^2 points, and a frame costs fixed + per_point * points * forces,
// times a noise factor.
struct Frames {
  double density = 4.0e6;  // points per unit radius squared (a 2M-point sphere's 20 spacings: ~6,000)
  double fixed_ns = 90'000.0;
  double per_point_ns = 12.0;
  std::size_t forces = 5;

  std::size_t points(double radius) const { return static_cast<std::size_t>(density * radius * radius); }
  double cost(std::size_t points) const {
    return fixed_ns + per_point_ns * static_cast<double>(points) * static_cast<double>(forces);
  }
  // The largest region whose frame costs `allowed`.
  double best_points(double allowed) const {
    return (allowed - fixed_ns) / (per_point_ns * static_cast<double>(forces));
  }
};

constexpr double kBudgetNs = 1.0e6;
constexpr double kFraction = 0.6;

TEST(RegionSizer, KeepsTheRadiusUntilAFrameIsObserved) {
  RegionSizer sizer(kFraction);
  EXPECT_FALSE(sizer.ready());
  EXPECT_EQ(sizer.next_radius(0.05, 1000, 5, kBudgetNs), 0.05);
  // Frames that moved nothing or have no usable time are not observations.
  sizer.observe(0, 5, 1e5);
  sizer.observe(1000, 0, 1e5);
  sizer.observe(1000, 5, std::numeric_limits<double>::quiet_NaN());
  sizer.observe(1000, 5, std::numeric_limits<double>::infinity());
  sizer.observe(1000, 5, -1.0);
  EXPECT_FALSE(sizer.ready());
  EXPECT_EQ(sizer.next_radius(0.05, 1000, 5, kBudgetNs), 0.05);
}

TEST(RegionSizer, GrowsByAtMostItsLimitAndSizesFromTheDearerOfAverageAndLastFrame) {
  RegionSizer sizer(kFraction);
  for (int k = 0; k < 10; ++k) sizer.observe(2000, 5, 300'000.0);
  EXPECT_DOUBLE_EQ(sizer.per_point_force_ns(), 300'000.0 / (2000.0 * 5.0));
  // Allowed 600 us: twice the points, held to the growth limit.
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.1, 2000, 5, kBudgetNs), 0.1 * std::sqrt(RegionSizer::kMaxGrowth));
  // A frame at twice the average's cost per point sizes the next from its own: the share pays
  // for 600 / 1,200 of its points.
  sizer.observe(2000, 5, 1'200'000.0);
  EXPECT_GT(sizer.per_point_force_ns(), 30.0);
  EXPECT_LT(sizer.per_point_force_ns(), 120.0);
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.1, 2000, 5, kBudgetNs), 0.1 * std::sqrt(0.5));
  // A cheap frame after it grows no faster than the average allows.
  sizer.observe(2000, 5, 100'000.0);
  const double by_average = kFraction * kBudgetNs / (sizer.per_point_force_ns() * 5.0) / 2000.0;
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.1, 2000, 5, kBudgetNs),
                   0.1 * std::sqrt(std::min(by_average, RegionSizer::kMaxGrowth)));
}

// Runs `frames` frames of the model from `radius`, each sized by the sizer from the last, with
// the measured time scaled by noise(k). Checks each step's growth; keeps the dearest frame's true
// cost in *worst_cost; returns the last radius.
template <class Noise>
double run(RegionSizer& sizer, const Frames& f, double radius, int frames, Noise noise, double* worst_cost) {
  std::size_t last = 0;
  for (int k = 0; k < frames; ++k) {
    const std::size_t points = std::max<std::size_t>(f.points(radius), 1);
    if (last > 0) {
      EXPECT_LE(static_cast<double>(points), RegionSizer::kMaxGrowth * static_cast<double>(last) * 1.001 + 1.0)
          << "frame " << k;
    }
    const double cost = f.cost(points);
    *worst_cost = std::max(*worst_cost, cost);
    sizer.observe(points, f.forces, cost * noise(k));
    radius = sizer.next_radius(radius, points, f.forces, kBudgetNs);
    last = points;
  }
  return radius;
}

TEST(RegionSizer, GrowsASmallRegionToTheBudgetAndStaysThere) {
  const Frames f;
  RegionSizer sizer(kFraction);
  double worst = 0.0;
  const double radius = run(
      sizer, f, 0.005, 200, [](int) { return 1.0; }, &worst);
  const double allowed = kFraction * kBudgetNs;
  // From below and never past it (the fixed part charged to the points only slows the
  // approach), to within a percent of the largest region the share pays for.
  EXPECT_NEAR(static_cast<double>(f.points(radius)), f.best_points(allowed), 0.01 * f.best_points(allowed));
  EXPECT_LE(worst, allowed * 1.0001);
}

TEST(RegionSizer, NoisyTimesKeepTheFramesNearTheirShare) {
  // Times scattered by +-20 % around the model (a shared machine), and every tenth frame
  // measured at 40 % of its cost (the fast outliers that grew the old rule's region fourfold):
  // no frame's true cost passes the share by more than a quarter.
  const Frames f;
  RegionSizer sizer(kFraction);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> scatter(0.8, 1.2);
  double worst = 0.0;
  run(
      sizer, f, 0.005, 600, [&](int k) { return k % 10 == 9 ? 0.4 : scatter(rng); }, &worst);
  EXPECT_LE(worst, 1.25 * kFraction * kBudgetNs);  // a quarter over the share, 0.75 of the tick
}

TEST(RegionSizer, ADearerModelShrinksTheRegionWithinAFewFrames) {
  // Converged, then every point costs three times as much (a stroke reaching a part where each
  // frame splits, say): within five frames the frames are back within their share.
  Frames f;
  RegionSizer sizer(kFraction);
  double worst = 0.0;
  double radius = run(
      sizer, f, 0.005, 200, [](int) { return 1.0; }, &worst);
  f.per_point_ns *= 3.0;
  for (int k = 0; k < 5; ++k) {
    const std::size_t points = f.points(radius);
    sizer.observe(points, f.forces, f.cost(points));
    radius = sizer.next_radius(radius, points, f.forces, kBudgetNs);
  }
  EXPECT_LE(f.cost(f.points(radius)), kFraction * kBudgetNs * 1.05);
}

TEST(RegionSizer, AShareItCannotMeetShrinksAllItMayAndANanBudgetToo) {
  RegionSizer sizer(kFraction);
  for (int k = 0; k < 5; ++k) sizer.observe(2000, 5, 900'000.0);  // over the share at any size
  const double shrunk = 0.1 * std::sqrt(RegionSizer::kMaxShrink);
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.1, 2000, 5, 0.0), shrunk);
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.1, 2000, 5, std::numeric_limits<double>::quiet_NaN()), shrunk);
}

// Before any global frame: one is tried (infinity, which the deformer clamps to the ball that
// holds the model and runs as the global frame) once the share would pay for kGlobalTrial of
// the model at the region's cost per point; a larger model grows its region as before.
TEST(RegionSizer, AGlobalFrameIsTriedWhenTheShareCouldPayForAPartOfTheModel) {
  const Frames f;
  RegionSizer sizer(kFraction);
  const std::size_t points = f.points(0.02);
  sizer.observe(points, f.forces, f.cost(points));
  // What the sizer affords at the region's cost (the fixed part charged to the points).
  const double afforded = kFraction * kBudgetNs * static_cast<double>(points) / f.cost(points);
  const auto within = static_cast<std::size_t>(afforded / RegionSizer::kGlobalTrial * 0.99);
  const auto beyond = static_cast<std::size_t>(afforded / RegionSizer::kGlobalTrial * 1.01);
  EXPECT_EQ(sizer.next_radius(0.02, points, f.forces, kBudgetNs, within), std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(sizer.next_radius(0.02, points, f.forces, kBudgetNs, beyond),
                   0.02 * std::sqrt(RegionSizer::kMaxGrowth));
  // Not before a frame was seen, nor without a force, nor for a NaN budget.
  EXPECT_EQ(RegionSizer(kFraction).next_radius(0.02, points, f.forces, kBudgetNs, 1), 0.02);
  EXPECT_EQ(sizer.next_radius(0.02, points, 0, kBudgetNs, 1), 0.02);
  EXPECT_LT(sizer.next_radius(0.02, points, f.forces, std::numeric_limits<double>::quiet_NaN(), 1), 0.02);
}

// Once a global frame was seen, its own cost decides: the global frame again while it fits
// the share; when it did not (a model too large, or more fingers), the region goes straight
// back to what the share pays for, and the trial is not repeated.
TEST(RegionSizer, OnceSeenTheGlobalFramesOwnCostDecides) {
  const Frames f;
  const double global_per_point_ns = f.per_point_ns / 5.0;  // no queries, no scattered reads
  const auto global_cost = [&](std::size_t n, std::size_t forces) {
    return f.fixed_ns + global_per_point_ns * static_cast<double>(n) * static_cast<double>(forces);
  };
  const double share = kFraction * kBudgetNs;
  RegionSizer sizer(kFraction);
  const std::size_t region = f.points(0.02);
  sizer.observe(region, f.forces, f.cost(region));
  // A model whose global frame fits the share with five fingers, not with five times as many
  // points.
  const std::size_t small = 30'000;
  ASSERT_LT(global_cost(small, f.forces), share);
  ASSERT_GT(global_cost(5 * small, f.forces), share);
  sizer.observe(small, f.forces, global_cost(small, f.forces), /*global=*/true);
  EXPECT_EQ(sizer.next_radius(3.0, small, f.forces, kBudgetNs, small), std::numeric_limits<double>::infinity());
  RegionSizer large_model(kFraction);
  large_model.observe(region, f.forces, f.cost(region));
  large_model.observe(5 * small, f.forces, global_cost(5 * small, f.forces), /*global=*/true);
  // Straight to what the share pays for at the region's cost, past the shrink limit.
  const double afforded = share * static_cast<double>(region) / f.cost(region);
  const double next = large_model.next_radius(3.0, 5 * small, f.forces, kBudgetNs, 5 * small);
  ASSERT_LT(afforded / (5.0 * small), RegionSizer::kMaxShrink);
  EXPECT_DOUBLE_EQ(next, 3.0 * std::sqrt(afforded / (5.0 * small)));
}

}  // namespace
}  // namespace sculpt::rt
