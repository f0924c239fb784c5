// The model's length scale: a regular grid's pitch, whatever duplicates and stray vertices the
// file adds, and a clear refusal when there is no length scale at all. Expected values come
// from the grids' construction, not from running the code.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sculpt/deform/model_scale.hpp"

namespace sculpt::deform {
namespace {

// A power of two, so every grid coordinate and every difference is exact in float: the nearest
// neighbour of every grid point is at exactly this distance.
constexpr double kPitch = 0.0625;

// 16 x 16 x 16 points, more than the 2000 samples, so the even sampling is exercised.
PointModel grid() {
  PointModel m;
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) {
      for (int k = 0; k < 16; ++k) m.push_back({1.0 + i * kPitch, -2.0 + j * kPitch, 0.5 + k * kPitch});
    }
  }
  return m;
}

TypicalSpacing spacing_of(const PointModel& m) { return typical_spacing(m, PointIndex(m)); }

std::string refusal(const PointModel& m) {
  try {
    spacing_of(m);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "a model without a length scale was given one";
  return {};
}

TEST(TypicalSpacing, RegularGridGivesItsPitch) {
  const TypicalSpacing s = spacing_of(grid());
  EXPECT_EQ(s.value, kPitch);
  EXPECT_EQ(s.statistic, "median nearest-neighbour distance over distinct points, 2000 samples");
}

TEST(TypicalSpacing, FullyDuplicatedGridGivesThePitch) {
  const PointModel g = grid();
  PointModel twice = g;
  for (std::size_t i = 0; i < g.size(); ++i) twice.push_back(g.position(i));  // a second copy appended
  EXPECT_EQ(spacing_of(twice).value, kPitch);
  // Six copies of every point, side by side: the first neighbours asked for are all copies, so
  // the search must widen to find a distinct one.
  PointModel six;
  for (std::size_t i = 0; i < g.size(); ++i) {
    for (int c = 0; c < 6; ++c) six.push_back(g.position(i));
  }
  EXPECT_EQ(spacing_of(six).value, kPitch);
}

TEST(TypicalSpacing, TenPercentDuplicatesChangeItByLessThanOnePercent) {
  PointModel m = grid();
  const std::size_t n = m.size();
  for (std::size_t i = 0; i < n; i += 10) m.push_back(m.position(i));
  EXPECT_NEAR(spacing_of(m).value, kPitch, 0.01 * kPitch);
}

TEST(TypicalSpacing, OneStrayVertexChangesItByLessThanOnePercent) {
  PointModel m = grid();
  m.push_back({1e4, 0.0, 0.0});
  EXPECT_NEAR(spacing_of(m).value, kPitch, 0.01 * kPitch);
  // Sampled too: with every point a sample, the stray one is among them.
  EXPECT_NEAR(typical_spacing(m, PointIndex(m), m.size()).value, kPitch, 0.01 * kPitch);
}

TEST(TypicalSpacing, SamplesEveryPointOfASmallModel) {
  PointModel m;
  m.push_back({0, 0, 0});
  m.push_back({3, 0, 0});
  m.push_back({3, 4, 0});
  // Nearest distances 3, 3 and 4: the median is 3.
  const TypicalSpacing s = spacing_of(m);
  EXPECT_EQ(s.value, 3.0);
  EXPECT_EQ(s.statistic, "median nearest-neighbour distance over distinct points, 3 samples");
}

TEST(TypicalSpacing, StacksTooDeepToSearchPastStillGiveTheDistinctSpacing) {
  // Two positions 0.5 apart, 300 copies of each: every sample sits in a stack deeper than the
  // neighbour search widens to, so the spacing comes from one copy of each position.
  PointModel m;
  for (int c = 0; c < 300; ++c) {
    m.push_back({0.0, 0.0, 0.0});
    m.push_back({0.5, 0.0, 0.0});
  }
  EXPECT_EQ(spacing_of(m).value, 0.5);
}

TEST(TypicalSpacing, AllCoincidentPointsHaveNoLengthScale) {
  PointModel m;
  for (int c = 0; c < 50; ++c) m.push_back({1.0, 2.0, 3.0});
  const std::string message = refusal(m);
  EXPECT_NE(message.find("the model's points all coincide: no length scale"), std::string::npos) << message;
  EXPECT_NE(message.find("all 50"), std::string::npos) << message;

  PointModel one;
  one.push_back({1.0, 2.0, 3.0});
  EXPECT_NE(refusal(one).find("no length scale"), std::string::npos);
  EXPECT_NE(refusal(PointModel()).find("no points"), std::string::npos);
}

TEST(TypicalSpacing, RefusesAnIndexOfAnotherModel) {
  const PointModel m = grid();
  PointModel other;
  other.push_back({0, 0, 0});
  EXPECT_THROW(typical_spacing(m, PointIndex(other)), std::invalid_argument);
  EXPECT_THROW(typical_spacing(m, PointIndex(m), 0), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
