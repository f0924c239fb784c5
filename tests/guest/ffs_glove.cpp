// A USB glove made of Linux's FunctionFS, for the guest test (scripts/guest_test.sh usb): run
// on a FunctionFS mount whose function scripts/guest's usb.sh put into a configfs gadget, it
// writes the function's descriptors to ep0 and then sends joint-angle samples of
// docs/glove-protocol.md on its bulk IN endpoint (interface 0), 200 a second, until killed.
// Meanwhile it reads its bulk OUT endpoint (interface 1: the host's glove source and haptic
// sink each claim an interface), decodes the haptic frames there with the protocol's decoder
// and appends one line per frame to HAPTIC_LOG, for the tests to compare with what they sent:
//
//   F <sequence> <device_time_us> <hand> <tick> <active_mask> <15 forces, finger by finger, x y z>
//
// (integers in decimal, forces as C hex floats, so they read back bit for bit), and a line
//   E <crc_errors> <framing_errors>
// whenever the decoder rejects a frame. While the gadget's controller is unbound its reads and
// writes fail or wait; it carries on when it is bound again.
//
//   ffs_glove MOUNT_DIR HAPTIC_LOG

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
#include <span>
#include <string>
#include <thread>

#include "sculpt/hal/frame_codec.hpp"

namespace {

// Interface 0 with one bulk IN endpoint (samples), interface 1 with one bulk OUT endpoint
// (haptic frames), at full and at high speed (dummy_hcd is high speed).
struct Descriptors {
  usb_functionfs_descs_head_v2 header;
  std::uint32_t fs_count;
  std::uint32_t hs_count;
  struct Speed {
    usb_interface_descriptor samples;
    usb_endpoint_descriptor_no_audio in;
    usb_interface_descriptor haptics;
    usb_endpoint_descriptor_no_audio out;
  } __attribute__((packed)) fs, hs;
} __attribute__((packed));

struct Strings {
  usb_functionfs_strings_head header;
  std::uint16_t language;
  char interface[sizeof "sculpt glove"];
} __attribute__((packed));

usb_interface_descriptor interface(std::uint8_t number) {
  usb_interface_descriptor i{};
  i.bLength = USB_DT_INTERFACE_SIZE;
  i.bDescriptorType = USB_DT_INTERFACE;
  i.bInterfaceNumber = number;
  i.bNumEndpoints = 1;
  i.bInterfaceClass = USB_CLASS_VENDOR_SPEC;
  i.iInterface = 1;
  return i;
}

// FunctionFS names the endpoint files after the addresses here: ep1 is IN, ep2 is OUT.
usb_endpoint_descriptor_no_audio bulk_endpoint(std::uint8_t address, std::uint16_t max_packet) {
  usb_endpoint_descriptor_no_audio e{};
  e.bLength = USB_DT_ENDPOINT_SIZE;
  e.bDescriptorType = USB_DT_ENDPOINT;
  e.bEndpointAddress = address;
  e.bmAttributes = USB_ENDPOINT_XFER_BULK;
  e.wMaxPacketSize = max_packet;
  return e;
}

Descriptors::Speed speed(std::uint16_t max_packet) {
  return {interface(0), bulk_endpoint(1 | USB_DIR_IN, max_packet), interface(1),
          bulk_endpoint(2 | USB_DIR_OUT, max_packet)};
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

// Reads the OUT endpoint for ever, logging each haptic frame decoded and each rejection.
void read_haptics(int ep2, int log) {
  sculpt::hal::FrameDecoder decoder;
  sculpt::hal::DecoderCounters logged{};
  std::array<std::uint8_t, 512> packet{};  // one high-speed bulk packet
  for (;;) {
    const ssize_t n = ::read(ep2, packet.data(), packet.size());
    if (n <= 0) {
      // Unbound or disabled (ESHUTDOWN and the like): what was half-received is gone.
      decoder.reset();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    decoder.feed(std::span<const std::uint8_t>(packet.data(), static_cast<std::size_t>(n)),
                 [&](const sculpt::hal::DecodedFrame& frame) {
                   if (frame.type != sculpt::hal::DecodedFrame::Type::kHaptic) return;
                   const sculpt::hal::HapticCommand& c = frame.haptic;
                   char line[640];
                   int length =
                       std::snprintf(line, sizeof line, "F %u %llu %u %u %u", frame.sequence,
                                     static_cast<unsigned long long>(frame.device_time_us),
                                     static_cast<unsigned>(c.hand), c.tick, static_cast<unsigned>(c.active_mask));
                   for (const auto& force : c.force)
                     for (const float component : force)
                       length += std::snprintf(line + length, sizeof line - static_cast<std::size_t>(length), " %a",
                                               static_cast<double>(component));
                   line[length++] = '\n';
                   write_all(log, line, static_cast<std::size_t>(length));  // O_APPEND: one line at a time
                 });
    const sculpt::hal::DecoderCounters& c = decoder.counters();
    if (c.crc_errors != logged.crc_errors || c.framing_errors != logged.framing_errors) {
      char line[64];
      const int length =
          std::snprintf(line, sizeof line, "E %llu %llu\n", static_cast<unsigned long long>(c.crc_errors),
                        static_cast<unsigned long long>(c.framing_errors));
      write_all(log, line, static_cast<std::size_t>(length));
      logged = c;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: ffs_glove MOUNT_DIR HAPTIC_LOG (MOUNT_DIR: a mounted functionfs)\n");
    return 2;
  }
  const std::string dir = argv[1];
  const int log = ::open(argv[2], O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (log < 0) {
    std::fprintf(stderr, "ffs_glove: cannot open %s: %s\n", argv[2], std::strerror(errno));
    return 1;
  }
  const int ep0 = ::open((dir + "/ep0").c_str(), O_RDWR);
  if (ep0 < 0) {
    std::fprintf(stderr, "ffs_glove: cannot open %s/ep0: %s\n", dir.c_str(), std::strerror(errno));
    return 1;
  }
  Descriptors d{};
  d.header.magic = FUNCTIONFS_DESCRIPTORS_MAGIC_V2;
  d.header.length = sizeof d;
  d.header.flags = FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC;
  d.fs_count = d.hs_count = 4;
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
  const int ep2 = ::open((dir + "/ep2").c_str(), O_RDWR);
  if (ep2 < 0) {
    std::fprintf(stderr, "ffs_glove: cannot open %s/ep2: %s\n", dir.c_str(), std::strerror(errno));
    return 1;
  }
  std::thread(read_haptics, ep2, log).detach();
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
