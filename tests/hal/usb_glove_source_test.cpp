// UsbGloveSource. Only set-up can be tested here: there is no glove (and no usbfs) on the
// build machine, so the transfer path, hot-unplug and reconnection are not exercised by any
// test. Those need the device, or a USB gadget (dummy_hcd + a FunctionFS glove), in a
// hardware-in-the-loop run.

#include "usb_glove_source.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace sculpt::hal {
namespace {

TEST(UsbGloveSource, StartWithoutTheDeviceNamesBothIds) {
  UsbConfig config;
  config.vendor_id = 0xfffe;  // not assigned to any vendor
  config.product_id = 0x0bad;
  UsbGloveSource source(config);
  try {
    source.start();
    FAIL() << "a device fffe:0bad was found";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("usb: ", 0), 0u) << what;
    EXPECT_NE(what.find("fffe:0bad"), std::string::npos) << what;
  }
  EXPECT_EQ(source.state(), SourceState::kStopped);
  source.stop();  // idempotent after a failed start
}

TEST(UsbGloveSource, RejectsAnOutEndpointAndANegativeInterface) {
  UsbConfig config;
  config.endpoint = 0x01;
  EXPECT_THROW(UsbGloveSource{config}, std::invalid_argument);
  config.endpoint = 0x81;
  config.interface_number = -1;
  EXPECT_THROW(UsbGloveSource{config}, std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::hal
