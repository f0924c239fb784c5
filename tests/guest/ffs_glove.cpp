// A USB glove made of Linux's FunctionFS, for the guest test (scripts/guest_test.sh usb): run
// on a FunctionFS mount whose function scripts/guest's usb.sh put into a configfs gadget, it
// writes the function's descriptors to ep0 and then sends joint-angle samples of
// docs/glove-protocol.md on its bulk IN endpoint, 200 a second, until killed. While the
// gadget's controller is unbound its writes fail or wait; it carries on when it is bound again.
//
//   ffs_glove MOUNT_DIR

#include <fcntl.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "sculpt/hal/frame_codec.hpp"

namespace {

// One interface with one bulk IN endpoint, at full and at high speed (dummy_hcd is high speed).
struct Descriptors {
  usb_functionfs_descs_head_v2 header;
  std::uint32_t fs_count;
  std::uint32_t hs_count;
  struct Speed {
    usb_interface_descriptor interface;
    usb_endpoint_descriptor_no_audio in;
  } __attribute__((packed)) fs, hs;
} __attribute__((packed));

struct Strings {
  usb_functionfs_strings_head header;
  std::uint16_t language;
  char interface[sizeof "sculpt glove"];
} __attribute__((packed));

Descriptors::Speed speed(std::uint16_t max_packet) {
  Descriptors::Speed s{};
  s.interface.bLength = USB_DT_INTERFACE_SIZE;
  s.interface.bDescriptorType = USB_DT_INTERFACE;
  s.interface.bNumEndpoints = 1;
  s.interface.bInterfaceClass = USB_CLASS_VENDOR_SPEC;
  s.interface.iInterface = 1;
  s.in.bLength = USB_DT_ENDPOINT_SIZE;
  s.in.bDescriptorType = USB_DT_ENDPOINT;
  s.in.bEndpointAddress = 1 | USB_DIR_IN;
  s.in.bmAttributes = USB_ENDPOINT_XFER_BULK;
  s.in.wMaxPacketSize = max_packet;
  return s;
}

bool write_all(int fd, const void* data, std::size_t size) {
  return ::write(fd, data, size) == static_cast<ssize_t>(size);
}

// Reads ep0's events (bind, enable, disable, unbind) and prints them for the console log.
void report_events(int ep0) {
  static constexpr std::array<const char*, 7> kNames = {"bind",  "unbind",  "enable", "disable",
                                                        "setup", "suspend", "resume"};
  std::array<usb_functionfs_event, 4> events{};
  for (;;) {
    const ssize_t n = ::read(ep0, events.data(), sizeof events);
    if (n < 0) {
      if (errno == EINTR) continue;
      return;
    }
    for (std::size_t i = 0; i < static_cast<std::size_t>(n) / sizeof events[0]; ++i) {
      const unsigned type = events[i].type;
      std::printf("ffs_glove: %s\n", type < kNames.size() ? kNames[type] : "event");
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: ffs_glove MOUNT_DIR (a mounted functionfs)\n");
    return 2;
  }
  const std::string dir = argv[1];
  const int ep0 = ::open((dir + "/ep0").c_str(), O_RDWR);
  if (ep0 < 0) {
    std::fprintf(stderr, "ffs_glove: cannot open %s/ep0: %s\n", dir.c_str(), std::strerror(errno));
    return 1;
  }
  Descriptors d{};
  d.header.magic = FUNCTIONFS_DESCRIPTORS_MAGIC_V2;
  d.header.length = sizeof d;
  d.header.flags = FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC;
  d.fs_count = d.hs_count = 2;
  d.fs = speed(64);
  d.hs = speed(512);
  Strings s{};
  s.header.magic = FUNCTIONFS_STRINGS_MAGIC;
  s.header.length = sizeof s;
  s.header.str_count = 1;
  s.header.lang_count = 1;
  s.language = 0x0409;
  std::memcpy(s.interface, "sculpt glove", sizeof s.interface);
  if (!write_all(ep0, &d, sizeof d) || !write_all(ep0, &s, sizeof s)) {
    std::fprintf(stderr, "ffs_glove: the kernel refused the descriptors: %s\n", std::strerror(errno));
    return 1;
  }
  std::thread(report_events, ep0).detach();
  const int ep1 = ::open((dir + "/ep1").c_str(), O_RDWR);
  if (ep1 < 0) {
    std::fprintf(stderr, "ffs_glove: cannot open %s/ep1: %s\n", dir.c_str(), std::strerror(errno));
    return 1;
  }
  std::printf("ffs_glove: ready\n");
  std::fflush(stdout);

  sculpt::hal::GloveSample sample;
  sample.hand = 0;
  sample.kind = sculpt::hal::SampleKind::kAngles;
  std::array<std::uint8_t, sculpt::hal::kMaxFrameBytes> frame{};
  for (std::uint32_t sequence = 0;; ++sequence) {
    sample.sequence = sequence;
    sample.angles[1] = {0.1f, 0.2f, 0.3f, static_cast<float>(sequence % 100) * 0.01f};
    const std::size_t n = sculpt::hal::encode_sample_frame(sample, frame);
    // Unbound or disabled, a write fails (ESHUTDOWN and the like) or waits: keep trying.
    if (!write_all(ep1, frame.data(), n)) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}
