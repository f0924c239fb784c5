#pragma once
// The glove on a CAN bus through Linux SocketCAN (docs/glove-can.md has the frame layout).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <thread>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/can_frame_codec.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sculpt/base/spsc_queue.hpp"

namespace sculpt::hal {

/// Reads glove samples from a SocketCAN raw socket bound to one interface. An I/O thread
/// poll()s the socket, reassembles each hand's segments (CanSampleDecoder) and queues
/// complete samples; CAN error frames are received and counted (error_frames; a bus-off
/// also bumps bus_off). If the interface goes down, or goes away (a USB adapter unplugged),
/// the state becomes kDisconnected (disconnects++) and comes back to kConnected with the next
/// frame (reconnects++); an interface that went away is looked for again every 200 ms.
class CanGloveSource final : public GloveSource {
 public:
  /// @throw std::invalid_argument when the interface name is empty or too long, or the ids
  ///   from base_id would pass the 29-bit range.
  CanGloveSource(const CanConfig& config, std::size_t queue_capacity = 1024);
  ~CanGloveSource() override;
  CanGloveSource(const CanGloveSource&) = delete;
  CanGloveSource& operator=(const CanGloveSource&) = delete;

  /// Opens and binds the socket and starts the I/O thread. No-op while running.
  /// @throw std::runtime_error "socketcan: AF_CAN is not available on this kernel (...)",
  ///   "socketcan: no interface 'can0'", or another "socketcan: ..." naming the interface.
  void start() override;
  void stop() override;
  std::size_t poll(std::span<GloveSample> out) noexcept override;
  SourceCounters counters() const noexcept override;
  SourceState state() const noexcept override { return state_.load(std::memory_order_acquire); }
  const char* name() const noexcept override { return "socketcan"; }

 private:
  void run() noexcept;
  void on_frame(const CanFrame& frame) noexcept;
  /// Opens and binds a new socket in place of the current one; false if it cannot yet.
  bool reopen_socket() noexcept;

  CanConfig config_;
  base::SpscQueue<GloveSample> queue_;
  AtomicSourceCounters counters_;
  std::atomic<SourceState> state_{SourceState::kStopped};
  std::atomic<bool> stop_requested_{false};
  int socket_ = -1;
  int wake_ = -1;  // eventfd that stop() signals so poll() returns at once
  std::array<CanSampleDecoder, kHands> decoders_;
  std::array<CanDecoderCounters, kHands> reported_{};  // decoder counts already added to counters_
  std::thread thread_;
};

/// Opens a SocketCAN raw socket on `interface` (CAN FD frames enabled when `fd`, error frames
/// received when `error_frames`) and binds it. Shared by the CAN source and sink.
/// @throw std::runtime_error as CanGloveSource::start describes.
int open_can_socket(const std::string& interface, bool fd, bool error_frames);

/// Returns `config` once its interface name fits Linux's and the ids from its base_id stay in
/// CAN's 29-bit range. `section` names the setting in errors ("glove.can", "haptic.can").
/// Shared by the CAN source and sink.
/// @throw std::invalid_argument naming `section`'s field.
CanConfig checked_can_config(const CanConfig& config, const std::string& section);

}  // namespace sculpt::hal
