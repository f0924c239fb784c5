#include "sculpt/hal/serial_frame_writer.hpp"

#include <poll.h>

#include <chrono>

namespace sculpt::hal {

SerialFrameWriter::SerialFrameWriter(const std::string& device, int baud)
    : device_(device), baud_(baud), port_(device, baud) {}

bool SerialFrameWriter::write_sample(const GloveSample& sample) noexcept {
  const std::size_t n = encode_sample_frame(sample, frame_);
  const bool ok = write_raw(std::span<const std::uint8_t>(frame_.data(), n));
  // Keep the host-to-glove direction drained, so a host sending haptics never stalls on us.
  if (port_.is_open()) pump_input();
  return ok;
}

bool SerialFrameWriter::write_raw(std::span<const std::uint8_t> bytes) noexcept {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::milliseconds(kWriteTimeoutMs);
  while (!bytes.empty()) {
    if (!port_.is_open()) return false;
    const IoResult r = port_.write(bytes);
    if (r.status == IoStatus::kGone) {
      port_.close();
      return false;
    }
    if (r.status == IoStatus::kOk) {
      bytes = bytes.subspan(r.bytes);
      continue;
    }
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return false;
    pollfd out{port_.fd(), POLLOUT, 0};
    ::poll(&out, 1, static_cast<int>(left.count()));
    if ((out.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
      port_.close();
      return false;
    }
  }
  return true;
}

bool SerialFrameWriter::reopen() {
  port_.close();
  decoder_.reset();
  return port_.try_open(device_, baud_, last_error_);
}

std::size_t SerialFrameWriter::pump_input() noexcept {
  std::size_t received = 0;
  while (port_.is_open()) {
    pollfd in{port_.fd(), POLLIN, 0};
    if (::poll(&in, 1, 0) <= 0 || in.revents == 0) break;
    const IoResult r = port_.read(input_);
    if (r.status != IoStatus::kOk) {
      // POLLIN or POLLHUP followed by nothing to read: the terminal was hung up.
      port_.close();
      break;
    }
    decoder_.feed(std::span<const std::uint8_t>(input_.data(), r.bytes), [&](const DecodedFrame& frame) {
      if (frame.type != DecodedFrame::Type::kHaptic) return;
      ++received;
      last_haptic_ = frame.haptic;
    });
  }
  haptic_frames_ += received;
  return received;
}

std::uint64_t SerialFrameWriter::haptic_frames_received() noexcept {
  pump_input();
  return haptic_frames_;
}

}  // namespace sculpt::hal
