#pragma once
// Haptic commands to the glove over SocketCAN (docs/glove-can.md has the frame layout).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/can_frame_codec.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "delivery_counts.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// Sends haptic commands as CAN frames (ids base + 0x80 + hand). send() only queues; the I/O
/// thread wakes every millisecond, takes what is queued, keeps the newest command per hand
/// (an older force is worthless once a newer one exists, and a classic bus cannot carry ten
/// frames per hand per millisecond) and writes it. Commands superseded that way count as
/// superseded; those refused by a full queue or not written by the kernel as dropped. If the
/// interface goes away (a USB adapter unplugged) the socket is opened again every 200 ms
/// until an interface of that name is back.
class CanHapticSink final : public HapticSink {
 public:
  /// @throw std::invalid_argument as CanGloveSource's constructor.
  CanHapticSink(const CanConfig& config, std::size_t queue_capacity = 256);
  ~CanHapticSink() override;
  CanHapticSink(const CanHapticSink&) = delete;
  CanHapticSink& operator=(const CanHapticSink&) = delete;

  /// @throw std::runtime_error as CanGloveSource::start.
  void start() override;
  void stop() override;
  bool send(const HapticCommand& command) noexcept override;
  std::uint64_t dropped() const noexcept override { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t superseded() const noexcept override { return superseded_.load(std::memory_order_relaxed); }
  const char* name() const noexcept override { return "socketcan"; }
  /// Commands written to the bus in full.
  std::uint64_t sent() const noexcept { return sent_.total(); }
  std::uint64_t delivered() const noexcept override { return sent(); }
  std::uint64_t delivered_in_contact(std::size_t hand) const noexcept override { return sent_.in_contact(hand); }

 private:
  void run() noexcept;
  bool write_command(const HapticCommand& command) noexcept;

  CanConfig config_;
  base::SpscQueue<HapticCommand> queue_;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> superseded_{0};
  DeliveryCounts sent_;
  std::atomic<bool> stop_requested_{false};
  int socket_ = -1;
  bool interface_gone_ = false;  // I/O thread only
  std::thread thread_;
};

}  // namespace sculpt::hal
