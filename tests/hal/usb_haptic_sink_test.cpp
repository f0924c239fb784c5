// UsbHapticSink without a device: its settings checks, start()'s error, the loop's side of the
// queue and the bound it puts on every force. The frames on the wire, the release on silence
// and the reconnection are tested against a FunctionFS glove in a booted kernel
// (tests/guest/usb_gadget_test.cpp, scripts/guest_test.sh usb).

#include "usb_haptic_sink.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sculpt/hal/backend_factory.hpp"

namespace sculpt::hal {
namespace {

UsbConfig absent_device() {
  UsbConfig config;
  config.vendor_id = 0xfffe;  // not assigned to any vendor
  config.product_id = 0x0bad;
  config.interface_number = 1;
  config.out_endpoint = 0x02;
  return config;
}

double magnitude(const Point3f& v) {
  return std::sqrt(double{v[0]} * v[0] + double{v[1]} * v[1] + double{v[2]} * v[2]);
}

// The message of the std::invalid_argument that constructing a sink with these settings throws.
std::string construction_error(const UsbConfig& config, float max_force = 4.0f, std::size_t queue = 16) {
  try {
    UsbHapticSink sink(config, max_force, queue);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(UsbHapticSink, StartWithoutTheDeviceNamesTheSinkAndBothIds) {
  UsbHapticSink sink(absent_device(), 4.0f);
  for (int attempt = 0; attempt < 2; ++attempt) {  // a failed start leaves it startable again
    try {
      sink.start();
      FAIL() << "a device fffe:0bad was found";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("usb haptic sink: ", 0), 0u) << what;
      EXPECT_NE(what.find("fffe:0bad"), std::string::npos) << what;
    }
    EXPECT_FALSE(sink.connected());
  }
  sink.stop();  // idempotent after a failed start
  sink.stop();
  EXPECT_EQ(sink.delivered(), 0u);
  EXPECT_EQ(sink.disconnects(), 0u);
}

TEST(UsbHapticSink, RejectsSettingsThatCannotWorkNamingTheKey) {
  UsbConfig config = absent_device();
  EXPECT_EQ(construction_error(config), "");
  config.out_endpoint = 0x81;  // an IN endpoint
  EXPECT_NE(construction_error(config).find("haptic.usb.out_endpoint: 129"), std::string::npos);
  config.out_endpoint = 0x00;  // the control endpoint
  EXPECT_NE(construction_error(config).find("haptic.usb.out_endpoint: 0"), std::string::npos);
  config = absent_device();
  config.interface_number = -1;
  EXPECT_NE(construction_error(config).find("haptic.usb.interface_number: -1"), std::string::npos);
  config = absent_device();
  EXPECT_NE(construction_error(config, 0.0f).find("haptic.max_force"), std::string::npos);
  EXPECT_NE(construction_error(config, -1.0f).find("haptic.max_force"), std::string::npos);
  EXPECT_NE(construction_error(config, std::numeric_limits<float>::quiet_NaN()).find("haptic.max_force"),
            std::string::npos);
  EXPECT_NE(construction_error(config, 4.0f, 0).find("haptic.queue_capacity"), std::string::npos);
}

TEST(UsbHapticSink, SendQueuesUpToTheCapacityAndCountsWhatItRefuses) {
  UsbHapticSink sink(absent_device(), 4.0f, 4);  // not started: nothing takes the queue
  HapticCommand c;
  for (std::uint32_t i = 0; i < 4; ++i) {
    c.tick = i;
    EXPECT_TRUE(sink.send(c)) << i;
  }
  EXPECT_FALSE(sink.send(c));
  EXPECT_EQ(sink.dropped(), 1u);
  HapticCommand third_hand;
  third_hand.hand = kHands;
  UsbHapticSink roomy(absent_device(), 4.0f, 4);
  EXPECT_FALSE(roomy.send(third_hand));
  EXPECT_EQ(roomy.dropped(), 1u);
  EXPECT_EQ(roomy.delivered(), 0u);
}

TEST(UsbHapticSink, BoundScalesAForceDownToTheLimitKeepingItsDirection) {
  HapticCommand c;
  c.active_mask = 0b111;
  c.force[0] = {30.0f, -40.0f, 0.0f};   // 50 N
  c.force[1] = {1.0f, 2.0f, 2.0f};      // 3 N: within the bound, left as it is
  c.force[2] = {3e38f, 3e38f, -3e38f};  // its square overflows a float
  EXPECT_TRUE(UsbHapticSink::bound(c, 4.0f));
  EXPECT_NEAR(c.force[0][0], 2.4f, 1e-6);
  EXPECT_NEAR(c.force[0][1], -3.2f, 1e-6);
  EXPECT_EQ(c.force[0][2], 0.0f);
  EXPECT_LE(magnitude(c.force[0]), 4.0 * (1 + 1e-7));
  EXPECT_EQ(c.force[1], (Point3f{1.0f, 2.0f, 2.0f}));
  EXPECT_NEAR(magnitude(c.force[2]), 4.0, 4e-6);
  EXPECT_NEAR(c.force[2][0], 4.0 / std::sqrt(3.0), 1e-6);
  EXPECT_NEAR(c.force[2][2], -4.0 / std::sqrt(3.0), 1e-6);
  EXPECT_EQ(c.active_mask, 0b111);  // still in contact, just bounded
}

TEST(UsbHapticSink, BoundZeroesANonFiniteFingerAndTakesItOutOfContact) {
  HapticCommand c;
  c.active_mask = 0b11001;
  c.force[0] = {0.5f, std::numeric_limits<float>::quiet_NaN(), 0.0f};
  c.force[3] = {0.0f, 0.0f, -std::numeric_limits<float>::infinity()};
  c.force[4] = {0.1f, 0.2f, 0.3f};
  EXPECT_TRUE(UsbHapticSink::bound(c, 4.0f));
  EXPECT_EQ(c.force[0], (Point3f{0.0f, 0.0f, 0.0f}));
  EXPECT_EQ(c.force[3], (Point3f{0.0f, 0.0f, 0.0f}));
  EXPECT_EQ(c.force[4], (Point3f{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(c.active_mask, 0b10000);
}

TEST(UsbHapticSink, BoundLeavesACommandWithinTheLimitUnchanged) {
  HapticCommand c;
  c.active_mask = 0b11111;
  for (std::size_t f = 0; f < kFingers; ++f) c.force[f] = {0.0f, 0.0f, -4.0f};  // exactly at the bound
  const HapticCommand before = c;
  EXPECT_FALSE(UsbHapticSink::bound(c, 4.0f));
  EXPECT_EQ(c.force, before.force);
  EXPECT_EQ(c.active_mask, before.active_mask);
}

TEST(UsbHapticSink, TheFactoryBuildsItForSinkUsb) {
  HapticConfig config;
  config.sink = SinkKind::kUsb;
  config.usb = absent_device();
  const std::unique_ptr<HapticSink> sink = make_haptic_sink(config);
  ASSERT_NE(sink, nullptr);
  EXPECT_STREQ(sink->name(), "usb");
  EXPECT_THROW(sink->start(), std::runtime_error);
  config.max_force = 0.0;
  EXPECT_THROW(make_haptic_sink(config), std::invalid_argument);
  EXPECT_EQ(HapticConfig{}.usb.interface_number, 1);  // the glove source's is 0
}

}  // namespace
}  // namespace sculpt::hal
