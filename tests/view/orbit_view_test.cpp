// The viewer's camera angles by key, drag and wheel: each move by its stated amount, the limits
// held, and nothing reported as a move that did not move.

#include "orbit_view.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace sculpt::view {
namespace {

constexpr ViewAngles kFirst{30.0, 20.0, 1.0};

TEST(OrbitView, KeysStepEachAngleAndRReturnsToTheFirstView) {
  OrbitView v(kFirst);
  EXPECT_TRUE(v.key(Key::kOrbitRight));
  EXPECT_DOUBLE_EQ(v.angles().azimuth_deg, 45.0);
  EXPECT_TRUE(v.key(Key::kOrbitLeft));
  EXPECT_TRUE(v.key(Key::kOrbitLeft));
  EXPECT_DOUBLE_EQ(v.angles().azimuth_deg, 15.0);
  EXPECT_TRUE(v.key(Key::kTiltUp));
  EXPECT_DOUBLE_EQ(v.angles().elevation_deg, 30.0);
  EXPECT_TRUE(v.key(Key::kTiltDown));
  EXPECT_TRUE(v.key(Key::kTiltDown));
  EXPECT_DOUBLE_EQ(v.angles().elevation_deg, 10.0);
  EXPECT_TRUE(v.key(Key::kCloser));
  EXPECT_DOUBLE_EQ(v.angles().zoom, 0.8);
  EXPECT_TRUE(v.key(Key::kFarther));
  EXPECT_TRUE(v.key(Key::kFarther));
  EXPECT_DOUBLE_EQ(v.angles().zoom, 1.25);
  EXPECT_FALSE(v.key(Key::kPause)) << "not a camera key";
  EXPECT_TRUE(v.key(Key::kResetView));
  EXPECT_EQ(v.angles().azimuth_deg, kFirst.azimuth_deg);
  EXPECT_EQ(v.angles().elevation_deg, kFirst.elevation_deg);
  EXPECT_EQ(v.angles().zoom, kFirst.zoom);
  EXPECT_FALSE(v.key(Key::kResetView)) << "already the first view";
}

TEST(OrbitView, TheAzimuthWrapsAndTheTiltAndZoomStopAtTheirLimits) {
  OrbitView v({170.0, 80.0, 0.6});
  EXPECT_TRUE(v.key(Key::kOrbitRight));
  EXPECT_DOUBLE_EQ(v.angles().azimuth_deg, -175.0);
  EXPECT_TRUE(v.key(Key::kTiltUp));
  EXPECT_EQ(v.angles().elevation_deg, 85.0);
  EXPECT_FALSE(v.key(Key::kTiltUp)) << "at the limit nothing moves";
  EXPECT_TRUE(v.key(Key::kCloser));
  EXPECT_EQ(v.angles().zoom, 0.5);
  EXPECT_FALSE(v.key(Key::kCloser));
  for (int k = 0; k < 20; ++k) v.key(Key::kFarther);
  EXPECT_EQ(v.angles().zoom, 4.0);
  for (int k = 0; k < 30; ++k) v.key(Key::kTiltDown);
  EXPECT_EQ(v.angles().elevation_deg, -85.0);
}

// A drag across the whole width turns the model half round, against the camera's orbit (its
// left side comes into view: the camera moves left, as the a key moves it); down the whole
// height tilts a quarter, the camera rising as w raises it. A drag in pieces moves as one.
TEST(OrbitView, ADragTurnsTheModelByTheFractionOfTheWindowItCrosses) {
  OrbitView v(kFirst);
  EXPECT_TRUE(v.drag(160.0, 0.0, 640, 480));
  EXPECT_DOUBLE_EQ(v.angles().azimuth_deg, 30.0 - 45.0);
  EXPECT_EQ(v.angles().elevation_deg, 20.0);
  EXPECT_TRUE(v.drag(0.0, 120.0, 640, 480));
  EXPECT_DOUBLE_EQ(v.angles().elevation_deg, 20.0 + 22.5);
  OrbitView pieces(kFirst), whole(kFirst);
  for (int k = 0; k < 4; ++k) pieces.drag(-20.0, -12.0, 640, 480);
  whole.drag(-80.0, -48.0, 640, 480);
  EXPECT_NEAR(pieces.angles().azimuth_deg, whole.angles().azimuth_deg, 1e-12);
  EXPECT_NEAR(pieces.angles().elevation_deg, whole.angles().elevation_deg, 1e-12);
  EXPECT_DOUBLE_EQ(whole.angles().azimuth_deg, 30.0 + 22.5);
  EXPECT_DOUBLE_EQ(whole.angles().elevation_deg, 20.0 - 9.0);
  // The key's direction: a drag left moves the camera as d does.
  OrbitView by_key(kFirst), by_drag(kFirst);
  by_key.key(Key::kOrbitRight);
  by_drag.drag(-640.0 * 15.0 / 180.0, 0.0, 640, 480);
  EXPECT_NEAR(by_drag.angles().azimuth_deg, by_key.angles().azimuth_deg, 1e-12);
  // Far down stops short of the pole; a drag with nothing in it, or not finite, is no move.
  EXPECT_TRUE(v.drag(0.0, 10000.0, 640, 480));
  EXPECT_EQ(v.angles().elevation_deg, 85.0);
  EXPECT_FALSE(v.drag(0.0, 0.0, 640, 480));
  EXPECT_FALSE(v.drag(std::numeric_limits<double>::quiet_NaN(), 5.0, 640, 480));
  EXPECT_FALSE(v.drag(5.0, 5.0, 0, 480));
}

TEST(OrbitView, EachWheelNotchIsAFifthCloserOrBackWithinTheZoomLimits) {
  OrbitView v(kFirst);
  EXPECT_TRUE(v.scroll(1.0));
  EXPECT_DOUBLE_EQ(v.angles().zoom, 0.8);
  EXPECT_TRUE(v.scroll(-2.0));
  EXPECT_DOUBLE_EQ(v.angles().zoom, 1.25);
  EXPECT_TRUE(v.scroll(0.5));  // a smooth wheel's half notch
  EXPECT_DOUBLE_EQ(v.angles().zoom, 1.25 * std::sqrt(0.8));
  EXPECT_FALSE(v.scroll(0.0));
  EXPECT_FALSE(v.scroll(std::numeric_limits<double>::infinity()));
  EXPECT_TRUE(v.scroll(50.0));
  EXPECT_EQ(v.angles().zoom, 0.5);
  EXPECT_FALSE(v.scroll(1.0));
  EXPECT_TRUE(v.scroll(-50.0));
  EXPECT_EQ(v.angles().zoom, 4.0);
}

}  // namespace
}  // namespace sculpt::view
