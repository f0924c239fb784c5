#include "sculpt/hal/serial_port.hpp"

#include <sys/eventfd.h>
#include <string>
#include <cmath>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace sculpt::hal {
namespace {

struct BaudEntry {
  int rate;
  speed_t code;
};

// termios wants the Bxxx constants, not numbers; only these rates exist for cfsetspeed.
constexpr std::array<BaudEntry, 30> kBaudTable = {{
    {50, B50},           {75, B75},           {110, B110},         {134, B134},         {150, B150},
    {200, B200},         {300, B300},         {600, B600},         {1200, B1200},       {1800, B1800},
    {2400, B2400},       {4800, B4800},       {9600, B9600},       {19200, B19200},     {38400, B38400},
    {57600, B57600},     {115200, B115200},   {230400, B230400},   {460800, B460800},   {500000, B500000},
    {576000, B576000},   {921600, B921600},   {1000000, B1000000}, {1152000, B1152000}, {1500000, B1500000},
    {2000000, B2000000}, {2500000, B2500000}, {3000000, B3000000}, {3500000, B3500000}, {4000000, B4000000},
}};

speed_t baud_code(int baud) {
  for (const BaudEntry& e : kBaudTable) {
    if (e.rate == baud) return e.code;
  }
  throw std::invalid_argument("serial baud " + std::to_string(baud) +
                              " is not a standard rate (e.g. 115200, 921600, 1000000)");
}

// The number of a Bxxx constant, or 0 for one the table does not hold (BOTHER, say).
int rate_of(speed_t code) {
  for (const BaudEntry& e : kBaudTable) {
    if (e.code == code) return e.rate;
  }
  return 0;
}

std::string os_error(const std::string& path, const char* step, int err) {
  return "serial " + path + ": " + step + ": " + std::strerror(err);
}

}  // namespace

SerialPort::SerialPort(const std::string& path, int baud) { open(path, baud); }

SerialPort::~SerialPort() { close(); }

SerialPort::SerialPort(SerialPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

bool SerialPort::is_standard_baud(int baud) noexcept {
  for (const BaudEntry& e : kBaudTable) {
    if (e.rate == baud) return true;
  }
  return false;
}

void SerialPort::open(const std::string& path, int baud) {
  std::string error;
  if (!try_open(path, baud, error)) throw std::runtime_error(error);
}

bool SerialPort::try_open(const std::string& path, int baud, std::string& error, bool exclusive) {
  const speed_t speed = baud_code(baud);
  close();
  path_ = path;
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    error = os_error(path, "open", errno);
    return false;
  }
  if (exclusive && ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd);
    if (err == EWOULDBLOCK) {
      throw InUse("serial " + path +
                  ": another program has it open for reading (it holds the device's lock): two readers "
                  "of one line would each get part of the glove's bytes");
    }
    error = os_error(path, "flock", err);
    return false;
  }
  termios tio{};
  const char* step = nullptr;
  if (::tcgetattr(fd, &tio) != 0) {
    step = "tcgetattr (not a terminal?)";
  } else {
    ::cfmakeraw(&tio);
    tio.c_cflag |= CLOCAL | CREAD;
    // What an earlier program left on must not outlive it, and cfmakeraw keeps these: hardware
    // flow control (CRTSCTS) would stall every frame written to a glove that does not drive
    // CTS, and IXOFF would put XOFF/XON bytes into the frames sent. One stop bit.
    tio.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | CSTOPB);
    tio.c_iflag &= ~static_cast<tcflag_t>(IXOFF | IXANY);
    // Reads return at once with whatever is there; the caller waits in poll(), not in read().
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0) {
      step = "cfsetspeed";
    } else if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
      step = "tcsetattr";
    } else if (::tcgetattr(fd, &tio) != 0) {
      step = "tcgetattr";
    }
  }
  if (step != nullptr) {
    const int err = errno;
    ::close(fd);
    error = os_error(path, step, err);
    return false;
  }
  // tcsetattr succeeds when any of the settings took, and a UART driver that cannot make the
  // rate from its clock keeps another one (the 8250's serial core falls back to the old rate or
  // 9600): read back what the line runs at.
  if (::cfgetospeed(&tio) != speed || ::cfgetispeed(&tio) != speed) {
    const int kept = rate_of(::cfgetospeed(&tio));
    ::close(fd);
    throw RateRefused("serial " + path + ": the driver runs the line at " +
                      (kept > 0 ? std::to_string(kept) + " baud" : std::string("another rate")) + ", not the " +
                      std::to_string(baud) + " baud asked: the device cannot make that rate");
  }
  fd_ = fd;
  return true;
}

void SerialPort::close() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

IoResult SerialPort::read(std::span<std::uint8_t> out) noexcept {
  if (fd_ < 0) return {IoStatus::kGone, 0, EBADF};
  for (;;) {
    const ssize_t n = ::read(fd_, out.data(), out.size());
    if (n > 0) return {IoStatus::kOk, static_cast<std::size_t>(n), 0};
    if (n == 0) return {IoStatus::kWouldBlock, 0, 0};
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return {IoStatus::kWouldBlock, 0, 0};
    return {IoStatus::kGone, 0, errno};
  }
}

std::size_t SerialPort::output_pending(int fd) noexcept {
  int pending = 0;
  if (fd < 0 || ::ioctl(fd, TIOCOUTQ, &pending) != 0 || pending < 0) return 0;
  return static_cast<std::size_t>(pending);
}

IoResult SerialPort::write(std::span<const std::uint8_t> bytes) noexcept {
  if (fd_ < 0) return {IoStatus::kGone, 0, EBADF};
  for (;;) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n >= 0) {
      return {n > 0 || bytes.empty() ? IoStatus::kOk : IoStatus::kWouldBlock, static_cast<std::size_t>(n), 0};
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return {IoStatus::kWouldBlock, 0, 0};
    return {IoStatus::kGone, 0, errno};
  }
}

void validate_serial_config(const SerialConfig& config, const char* who) {
  if (config.device.empty()) throw std::invalid_argument(std::string(who) + ": device path is empty");
  if (!SerialPort::is_standard_baud(config.baud)) {
    throw std::invalid_argument(std::string(who) + " " + config.device + ": baud " + std::to_string(config.baud) +
                                " is not a standard rate (e.g. 115200, 921600, 1000000)");
  }
  if (!std::isfinite(config.reconnect_interval_ms) || config.reconnect_interval_ms <= 0.0) {
    throw std::invalid_argument(std::string(who) + " " + config.device +
                                ": reconnect_interval_ms must be positive and finite");
  }
}

void require_character_device_if_present(const std::string& device, const std::string& who) {
  struct stat st {};
  if (::stat(device.c_str(), &st) == 0 && !S_ISCHR(st.st_mode)) {
    throw std::runtime_error(who + " " + device + ": exists but is not a character device (a serial port or pty)");
  }
}

int make_wake_fd(const std::string& who) {
  const int fd = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (fd < 0) throw std::runtime_error(who + ": eventfd: " + std::strerror(errno));
  return fd;
}

}  // namespace sculpt::hal
