// The Δs dead band: strictly more than Δs is a move, exactly Δs is not, and the last three
// accepted positions are kept in order. Boundary cases use coordinates that are exact in
// binary, so "exactly Δs" is exact arithmetic, not a rounding accident.
#include "sculpt/rt/dead_band.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace sculpt::rt {
namespace {

using P = std::array<double, 3>;

TEST(DeadBand, FirstPositionIsAccepted) {
  DeadBand band(0.5);
  EXPECT_EQ(band.history_size(), 0u);
  EXPECT_TRUE(band.offer({1.0, 2.0, 3.0}));
  EXPECT_EQ(band.history_size(), 1u);
  EXPECT_EQ(band.current(), (P{1.0, 2.0, 3.0}));
}

TEST(DeadBand, ExactlyDeltaSIsNotAMoveAndOneUlpMoreIs) {
  DeadBand band(0.5);
  band.offer({0.0, 0.0, 0.0});
  EXPECT_FALSE(band.offer({0.5, 0.0, 0.0}));
  EXPECT_FALSE(band.offer({0.0, -0.5, 0.0}));
  EXPECT_FALSE(band.offer({0.0, 0.0, 0.5}));
  EXPECT_TRUE(band.offer({std::nextafter(0.5, 1.0), 0.0, 0.0}));
  EXPECT_EQ(band.current()[0], std::nextafter(0.5, 1.0));
}

TEST(DeadBand, DiagonalBoundaryIsEuclidean) {
  // (0.375, 0.5, 0) has length 0.625 exactly (a 3-4-5 triangle over 8).
  DeadBand band(0.625);
  band.offer({1.0, 1.0, 1.0});
  EXPECT_FALSE(band.offer({1.375, 1.5, 1.0}));
  EXPECT_FALSE(band.offer({0.625, 0.5, 1.0}));
  // Each coordinate alone is well inside Δs: the test is on the length, not per axis.
  EXPECT_TRUE(band.offer({1.375, std::nextafter(1.5, 2.0), 1.0}));
  // 3-D: (2, 3, 6) has length 7.
  DeadBand cube(7.0);
  cube.offer({0.0, 0.0, 0.0});
  EXPECT_FALSE(cube.offer({2.0, -3.0, 6.0}));
  EXPECT_TRUE(cube.offer({2.0, -3.0, std::nextafter(6.0, 7.0)}));
}

TEST(DeadBand, MeasuresFromTheLastAcceptedPositionNotTheLastOffered) {
  DeadBand band(1.0);
  band.offer({0.0, 0.0, 0.0});
  // Creeping by 0.25 at a time: each step is small, but the fifth is 1.25 from the origin.
  EXPECT_FALSE(band.offer({0.25, 0.0, 0.0}));
  EXPECT_FALSE(band.offer({0.5, 0.0, 0.0}));
  EXPECT_FALSE(band.offer({0.75, 0.0, 0.0}));
  EXPECT_FALSE(band.offer({1.0, 0.0, 0.0}));
  EXPECT_TRUE(band.offer({1.25, 0.0, 0.0}));
  EXPECT_EQ(band.current(), (P{1.25, 0.0, 0.0}));
  EXPECT_EQ(band.previous(), (P{0.0, 0.0, 0.0}));
  EXPECT_EQ(band.accepted_count(), 2u);
}

TEST(DeadBand, KeepsTheLastThreeAcceptedInOrder) {
  DeadBand band(0.5);
  EXPECT_TRUE(band.offer({0.0, 0.0, 0.0}));
  EXPECT_TRUE(band.offer({1.0, 0.0, 0.0}));
  EXPECT_EQ(band.history_size(), 2u);
  EXPECT_FALSE(band.offer({1.25, 0.0, 0.0}));  // refused: no shift
  EXPECT_TRUE(band.offer({2.0, 0.0, 0.0}));
  EXPECT_EQ(band.history_size(), 3u);
  EXPECT_EQ(band.current(), (P{2.0, 0.0, 0.0}));
  EXPECT_EQ(band.previous(), (P{1.0, 0.0, 0.0}));
  EXPECT_EQ(band.earlier(), (P{0.0, 0.0, 0.0}));
  EXPECT_TRUE(band.offer({2.0, 3.0, 0.0}));
  EXPECT_EQ(band.history_size(), 3u);
  EXPECT_EQ(band.current(), (P{2.0, 3.0, 0.0}));
  EXPECT_EQ(band.previous(), (P{2.0, 0.0, 0.0}));
  EXPECT_EQ(band.earlier(), (P{1.0, 0.0, 0.0}));
  EXPECT_EQ(band.accepted_count(), 4u);
}

TEST(DeadBand, ZeroDeltaSAcceptsAnyChangeButNotARepeat) {
  DeadBand band(0.0);
  EXPECT_TRUE(band.offer({1.0, 1.0, 1.0}));
  EXPECT_FALSE(band.offer({1.0, 1.0, 1.0}));
  EXPECT_TRUE(band.offer({1.0, 1.0, std::nextafter(1.0, 2.0)}));
}

TEST(DeadBand, NonFinitePositionIsRefusedAndChangesNothing) {
  DeadBand band(0.1);
  band.offer({0.0, 0.0, 0.0});
  EXPECT_FALSE(band.offer({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0}));
  EXPECT_FALSE(band.offer({0.0, std::numeric_limits<double>::infinity(), 0.0}));
  EXPECT_EQ(band.history_size(), 1u);
  EXPECT_EQ(band.current(), (P{0.0, 0.0, 0.0}));
  DeadBand fresh(0.1);
  EXPECT_FALSE(fresh.offer({0.0, 0.0, std::numeric_limits<double>::quiet_NaN()}));
  EXPECT_EQ(fresh.history_size(), 0u);
}

TEST(DeadBand, ResetForgetsEverything) {
  DeadBand band(0.5);
  band.offer({0.0, 0.0, 0.0});
  band.offer({1.0, 0.0, 0.0});
  band.reset();
  EXPECT_EQ(band.history_size(), 0u);
  EXPECT_EQ(band.accepted_count(), 0u);
  // Would be inside the band of the old position; after reset it is simply the first.
  EXPECT_TRUE(band.offer({1.25, 0.0, 0.0}));
  EXPECT_EQ(band.history_size(), 1u);
  EXPECT_EQ(band.current(), (P{1.25, 0.0, 0.0}));
}

// Against an independent oracle: the distance by std::hypot (a different formula), away from
// the boundary where the two may round differently.
TEST(DeadBand, AgreesWithAHypotOracleOnARandomWalk) {
  std::mt19937 rng(42);
  std::normal_distribution<double> step(0.0, 0.05);
  const double ds = 0.1;
  DeadBand band(ds);
  P p{0.0, 0.0, 0.0}, last{0.0, 0.0, 0.0};
  band.offer(p);
  int accepted = 0, checked = 0;
  for (int i = 0; i < 20000; ++i) {
    for (double& c : p) c += step(rng);
    const double d = std::hypot(p[0] - last[0], p[1] - last[1], p[2] - last[2]);
    const bool got = band.offer(p);
    if (std::abs(d - ds) > 1e-12) {
      ++checked;
      ASSERT_EQ(got, d > ds) << "step " << i << " d=" << d;
    }
    if (got) {
      last = p;
      ++accepted;
    }
  }
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(checked, 19000);
}

TEST(DeadBand, RejectsABadDeltaS) {
  EXPECT_THROW(DeadBand(-0.1), std::invalid_argument);
  EXPECT_THROW(DeadBand{std::numeric_limits<double>::quiet_NaN()}, std::invalid_argument);
  EXPECT_THROW(DeadBand{std::numeric_limits<double>::infinity()}, std::invalid_argument);
  // The value as %g prints it: std::to_string printed -1e-9 as -0.000000.
  try {
    DeadBand(-1e-9);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dead band: delta_s must be finite and >= 0, got -1e-09");
  }
}

}  // namespace
}  // namespace sculpt::rt
