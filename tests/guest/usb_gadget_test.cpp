// The USB source against a real USB device in a booted kernel: the FunctionFS glove
// (tests/guest/ffs_glove.cpp) on dummy_hcd, set up by tests/guest/usb.sh, which names the
// configfs gadget in GLOVE_GADGET. Skips, saying so, anywhere else.

#include <gtest/gtest.h>

#include <libusb.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <thread>

#include "usb_glove_source.hpp"

namespace sculpt::hal {
namespace {

constexpr std::uint16_t kVendor = 0x1209;  // pid.codes' test ids, as usb.sh gives the gadget
constexpr std::uint16_t kProduct = 0x0001;

std::string gadget() {
  const char* g = std::getenv("GLOVE_GADGET");
  return g != nullptr ? g : "";
}

// Binds the gadget to the controller usb.sh named, or unbinds it ("" = unplug).
bool set_udc(const std::string& udc) {
  std::ofstream file(gadget() + "/UDC");
  file << udc << '\n';
  file.close();
  return !file.fail();
}

std::string bound_udc() {
  const char* u = std::getenv("GLOVE_UDC");
  return u != nullptr ? u : "dummy_udc.0";
}

bool eventually(const std::function<bool()>& done, int seconds = 10) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

// The gadget's bulk IN endpoint as the host enumerated it (FunctionFS may renumber).
std::uint8_t in_endpoint() {
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) return 0;
  std::uint8_t found = 0;
  libusb_device_handle* h = libusb_open_device_with_vid_pid(ctx, kVendor, kProduct);
  if (h != nullptr) {
    libusb_config_descriptor* config = nullptr;
    if (libusb_get_active_config_descriptor(libusb_get_device(h), &config) == 0) {
      const libusb_interface_descriptor& alt = config->interface[0].altsetting[0];
      for (int e = 0; e < alt.bNumEndpoints; ++e)
        if (alt.endpoint[e].bEndpointAddress & LIBUSB_ENDPOINT_IN) found = alt.endpoint[e].bEndpointAddress;
      libusb_free_config_descriptor(config);
    }
    libusb_close(h);
  }
  libusb_exit(ctx);
  return found;
}

class UsbGadget : public ::testing::Test {
 protected:
  void SetUp() override {
    if (gadget().empty()) GTEST_SKIP() << "no FunctionFS glove here (GLOVE_GADGET unset; scripts/guest_test.sh usb)";
    ASSERT_TRUE(eventually([&] { return (config_.endpoint = in_endpoint()) != 0; }))
        << "no device " << std::hex << kVendor << ":" << kProduct << " with an IN endpoint";
    config_.vendor_id = kVendor;
    config_.product_id = kProduct;
    config_.transfer = UsbConfig::Transfer::kBulk;
  }
  // Polls until `want` samples in all have come; false after 10 s.
  bool receive(UsbGloveSource& source, std::size_t want) {
    return eventually([&] {
      received_ += source.poll(std::span(buffer_));
      return received_ >= want;
    });
  }
  UsbConfig config_;
  std::array<GloveSample, 64> buffer_{};
  std::size_t received_ = 0;
};

TEST_F(UsbGadget, SourceReadsTheGlovesFrames) {
  UsbGloveSource source(config_);
  source.start();
  ASSERT_TRUE(receive(source, 50)) << received_ << " samples";
  EXPECT_EQ(source.state(), SourceState::kConnected);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.crc_errors + c.framing_errors, 0u);
  EXPECT_EQ(buffer_[0].kind, SampleKind::kAngles);
  EXPECT_FLOAT_EQ(buffer_[0].angles[1][0], 0.1f);
  source.stop();
}

TEST_F(UsbGadget, UnbindingTheControllerIsAnUnplugAndRebindingAReconnect) {
  UsbGloveSource source(config_);
  source.start();
  ASSERT_TRUE(receive(source, 20));
  ASSERT_TRUE(set_udc("")) << "cannot unbind " << gadget();
  const bool gone = eventually([&] { return source.state() == SourceState::kDisconnected; });
  ASSERT_TRUE(set_udc(bound_udc())) << "cannot bind " << gadget() << " to " << bound_udc();
  ASSERT_TRUE(gone) << "the source did not notice the unplug";
  EXPECT_EQ(source.counters().disconnects, 1u);
  const std::size_t before = received_;
  ASSERT_TRUE(eventually([&] { return source.state() == SourceState::kConnected; })) << "no reconnect";
  ASSERT_TRUE(receive(source, before + 20)) << "no samples after the reconnect";
  EXPECT_EQ(source.counters().reconnects, 1u);
  source.stop();
}

}  // namespace
}  // namespace sculpt::hal
