#pragma once
// Where the contact forces go for haptic feedback (lcm, serial, can, usb).

#include <array>
#include <cstddef>
#include <cstdint>

#include "sculpt/hal/glove_sample.hpp"

namespace sculpt::hal {

/// One hand's fingertip forces for one tick, in the glove frame (newtons by convention; the
/// scene's registration scale maps the model's force units).
struct HapticCommand {
  std::uint8_t hand = 0;
  std::uint32_t tick = 0;
  std::uint8_t active_mask = 0;  ///< bit f set: finger f is in contact
  std::array<Point3f, kFingers> force{};
};

/// Set-up may throw; send() runs in the loop: it only queues for the sink's I/O thread,
/// noexcept and allocation-free, and returns false when the queue was full (counted).
class HapticSink {
 public:
  virtual ~HapticSink() = default;
  virtual void start() = 0;
  virtual void stop() = 0;
  virtual bool send(const HapticCommand& command) noexcept = 0;
  /// Commands that could not be delivered (queue full, link down, write timed out).
  virtual std::uint64_t dropped() const noexcept = 0;
  /// Commands that reached the link (published, written, sent).
  virtual std::uint64_t delivered() const noexcept = 0;
  /// Of those, the commands of `hand` that carried a contact (a non-zero active mask): what
  /// that hand could feel, without the idle and release frames. 0 for a hand that does not exist.
  virtual std::uint64_t delivered_in_contact(std::size_t hand) const noexcept = 0;
  /// Commands deliberately not sent because a newer one for the same hand replaced them
  /// before the link had room: a slow link carries the newest force, never a backlog.
  virtual std::uint64_t superseded() const noexcept { return 0; }
  virtual const char* name() const noexcept = 0;
};

}  // namespace sculpt::hal
