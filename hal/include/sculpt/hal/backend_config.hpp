#pragma once
// Settings of each glove backend and haptic sink, as the scene file gives them.

#include <cstdint>
#include <string>
#include <vector>

#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// One finger's scripted path for the simulated glove: positions (glove frame) at times,
/// linearly interpolated; approach, press, hold, release, sweep and squeeze are all keyframes.
struct Keyframe {
  double time_s = 0.0;
  double x = 0.0, y = 0.0, z = 0.0;
};

struct FingerScript {
  std::uint8_t hand = 0;
  std::uint8_t finger = 1;          ///< 0 thumb .. 4 little
  std::vector<Keyframe> keyframes;  ///< ascending time
};

struct SimConfig {
  double rate_hz = 80.0;  ///< the thesis's glove ran at about 80 Hz
  std::uint64_t seed = 1;
  double jitter_stddev = 0.0;        ///< Gaussian noise per coordinate, glove units
  double dropout_probability = 0.0;  ///< chance that a sample is never sent
  double latency_ms = 0.0;           ///< delay between a sample's device time and its delivery
  bool repeat = false;               ///< loop the script; otherwise hold the last keyframe
  double duration_s = 0.0;  ///< stop producing after this (0: the last keyframe's time, or forever with repeat)
  std::vector<FingerScript> fingers;
};

struct SerialConfig {
  std::string device;  ///< e.g. /dev/ttyUSB0 or a pty's /dev/pts/N
  int baud = 921600;
  double reconnect_interval_ms = 200.0;
};

struct UsbConfig {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  int interface_number = 0;
  std::uint8_t endpoint = 0x81;      ///< IN endpoint
  std::uint8_t out_endpoint = 0x01;  ///< OUT endpoint for haptic frames (the usb haptic sink)
  enum class Transfer { kInterrupt, kBulk } transfer = Transfer::kInterrupt;
};

struct LcmConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string glove_channel = "SCULPT_GLOVE";
  std::string haptic_channel = "SCULPT_HAPTIC";
};

struct CanConfig {
  std::string interface = "can0";
  bool fd = true;                 ///< CAN FD (64-byte frames) or classic CAN (8 bytes)
  std::uint32_t base_id = 0x100;  ///< see docs/glove-can.md for the layout
};

enum class Backend { kSim, kSerial, kUsb, kLcm, kSocketCan };

struct GloveConfig {
  Backend backend = Backend::kSim;
  std::size_t queue_capacity = 1024;  ///< samples between the I/O thread and the loop
  SimConfig sim;
  SerialConfig serial;
  UsbConfig usb;
  LcmConfig lcm;
  CanConfig can;
};

enum class SinkKind { kNone, kLcm, kSerial, kCan, kUsb };

struct HapticConfig {
  SinkKind sink = SinkKind::kNone;
  std::size_t queue_capacity = 256;
  SerialConfig serial;
  LcmConfig lcm;
  CanConfig can;
  /// The usb sink's device: ids, the interface holding the OUT endpoint (one of its own when
  /// the USB source reads the same glove: an interface is claimed once), out_endpoint, transfer.
  UsbConfig usb{.interface_number = 1};
  double max_force = 4.0;  ///< N: the usb sink's own bound on a finger's force (the scene's haptic.max_force)
};

}  // namespace sculpt::hal
