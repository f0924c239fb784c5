// The factory builds a backend only where the build has it, and otherwise says which option
// brings it in. Built in every configuration, the minimal one (no USB, CAN or LCM) included.

#include "sculpt/hal/backend_factory.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace sculpt::hal {
namespace {

TEST(BackendFactory, AUsbHapticSinkExistsOnlyInABuildWithUsb) {
  HapticConfig config;
  config.sink = SinkKind::kUsb;
  config.usb.vendor_id = 0xfffe;
  config.usb.product_id = 0x0bad;
#if SCULPT_HAS_USB
  const std::unique_ptr<HapticSink> sink = make_haptic_sink(config);
  ASSERT_NE(sink, nullptr);
  EXPECT_STREQ(sink->name(), "usb");
#else
  try {
    make_haptic_sink(config);
    FAIL() << "a usb haptic sink in a build without USB";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "the usb haptic sink was left out of this build; reconfigure with -DSCULPT_WITH_USB=ON");
  }
#endif
}

TEST(BackendFactory, NoSinkIsNull) { EXPECT_EQ(make_haptic_sink(HapticConfig{}), nullptr); }

}  // namespace
}  // namespace sculpt::hal
