#pragma once
// A serial device (or pseudo-terminal) opened raw and non-blocking, closed on destruction.

#include "sculpt/hal/backend_config.hpp"
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace sculpt::hal {

/// Upper bound on one wait of a serial I/O thread (the glove source's and the haptic sink's).
/// stop() wakes the thread through an eventfd, so this only matters if that wake were lost; it
/// costs a wake-up ten times a second.
inline constexpr int kSerialPollTimeoutMs = 100;

/// Outcome of one read or write on a SerialPort.
enum class IoStatus : std::uint8_t {
  kOk,          ///< some bytes moved (see the count)
  kWouldBlock,  ///< nothing to read, or no room to write, right now
  kGone,        ///< the device disappeared (hang-up, EIO, unplugged): close and reopen
};

/// Result of SerialPort::read and SerialPort::write.
struct IoResult {
  IoStatus status = IoStatus::kWouldBlock;
  std::size_t bytes = 0;
  int error = 0;  ///< errno for kGone, when there was one
};

/// RAII owner of a serial file descriptor: opened O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC,
/// termios raw (cfmakeraw, CLOCAL | CREAD, VMIN = 0, VTIME = 0; no flow control, one stop bit,
/// whatever an earlier program left set) at a standard baud rate.
/// Move-only. Not thread-safe, except that read and write may run on different threads.
class SerialPort {
 public:
  /// A closed port.
  SerialPort() noexcept = default;
  /// Opens `path` at `baud`. Throws as open() does.
  SerialPort(const std::string& path, int baud);
  ~SerialPort();
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Closes any open device, then opens `path` at `baud`.
  /// @throw std::invalid_argument when `baud` is not a standard rate (see is_standard_baud)
  /// @throw std::runtime_error "serial <path>: <step>: <strerror>" when the device cannot be
  ///        opened or configured
  void open(const std::string& path, int baud);

  /// The device opened but runs the line at another rate than the one asked (a UART whose
  /// clock cannot make it: Linux's serial core then keeps the old rate or 9600, and tcsetattr
  /// still succeeds). A configuration error, not a missing device: retrying cannot help.
  class RateRefused : public std::runtime_error {
   public:
    using std::runtime_error::runtime_error;
  };

  /// With `exclusive`, another program holds the device's exclusive lock (flock, as pyserial's
  /// exclusive mode takes it): two readers of one line would each get part of its bytes.
  class InUse : public std::runtime_error {
   public:
    using std::runtime_error::runtime_error;
  };

  /// Like open(), but reports an OS failure by returning false and leaving the message in
  /// `error` (for reconnect loops, where a missing device is the normal case). `exclusive`:
  /// take the device's exclusive lock (flock, not blocking), held until close().
  /// @throw std::invalid_argument when `baud` is not a standard rate
  /// @throw RateRefused "serial <path>: the driver runs the line at 9600 baud, not the 921600
  ///        baud asked: ..." (the device is left closed)
  /// @throw InUse "serial <path>: another program has it open ..." (left closed)
  bool try_open(const std::string& path, int baud, std::string& error, bool exclusive = false);

  /// Closes the device. Idempotent.
  void close() noexcept;

  bool is_open() const noexcept { return fd_ >= 0; }
  /// The file descriptor, for poll(); -1 when closed.
  int fd() const noexcept { return fd_; }
  /// The path given to the last open.
  const std::string& path() const noexcept { return path_; }

  /// Reads what is available, up to out.size() bytes; never blocks. A hung-up terminal reads
  /// as kGone; with VMIN = VTIME = 0 an idle one reads 0 bytes, reported as kWouldBlock, so a
  /// caller tells the two apart by calling only after poll() reported POLLIN or POLLHUP.
  IoResult read(std::span<std::uint8_t> out) noexcept;
  /// Writes as much of `bytes` as the device takes now; never blocks.
  IoResult write(std::span<const std::uint8_t> bytes) noexcept;

  /// Bytes written but not yet sent by the driver (TIOCOUTQ); 0 when closed or unknown. A pty
  /// always reports 0: its bytes wait in the reader's buffer instead.
  static std::size_t output_pending(int fd) noexcept;

  /// True for the rates the termios table knows (50 .. 4000000).
  static bool is_standard_baud(int baud) noexcept;

 private:
  int fd_ = -1;
  std::string path_;
};

/// Checks the settings a serial backend needs before it starts; throws std::invalid_argument
/// naming `who` (e.g. "serial glove") and the device: empty path, non-standard baud, a
/// reconnect interval that is not positive and finite.
void validate_serial_config(const SerialConfig& config, const char* who);

/// At start: a device path that exists must be a character device (a serial port or a pty); a
/// file or folder there would be read as a glove or written to as one. A path that does not
/// exist yet is left to the backend's reconnects (a glove not plugged in). Throws
/// std::runtime_error "WHO DEVICE: exists but is not a character device (a serial port or pty)".
void require_character_device_if_present(const std::string& device, const std::string& who);

/// A non-blocking eventfd that wakes an I/O thread out of poll(); throws std::runtime_error
/// naming `who` when the kernel refuses one.
int make_wake_fd(const std::string& who);

}  // namespace sculpt::hal
