#pragma once
// A pseudo-terminal pair for the serial tests: the test holds the master, the code under test
// opens the slave by path.

#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace sculpt::hal::testing_support {

using Bytes = std::vector<std::uint8_t>;

// A pseudo-terminal pair. The slave is set raw at once so nothing the test writes before the
// code under test opens it is echoed or line-edited.
class Pty {
 public:
  Pty() {
    if (::openpty(&master_, &slave_, nullptr, nullptr, nullptr) != 0) {
      throw std::runtime_error(std::string("openpty: ") + std::strerror(errno));
    }
    termios tio{};
    ::tcgetattr(slave_, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(slave_, TCSANOW, &tio);
    slave_path_ = ::ttyname(slave_);
  }
  ~Pty() { close(); }
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;

  /// Closes both ends: for whoever has the slave open, the device is gone.
  void close() {
    if (master_ >= 0) ::close(master_);
    if (slave_ >= 0) ::close(slave_);
    master_ = slave_ = -1;
  }
  int master() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }

  void write(const Bytes& bytes) const {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      ASSERT_GT(n, 0) << std::strerror(errno);
      done += static_cast<std::size_t>(n);
    }
  }

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string slave_path_;
};

}  // namespace sculpt::hal::testing_support
