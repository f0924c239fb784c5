#include "serial_device_check.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sculpt::tools {

std::string serial_device_problem(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return "no such device (not plugged in, or a typo?)";
    return std::string("cannot use it: ") + std::strerror(errno);
  }
  if (S_ISDIR(info.st_mode)) return "a folder, not a serial device";
  if (S_ISREG(info.st_mode)) return "a regular file, not a serial device";
  if (S_ISFIFO(info.st_mode)) return "a FIFO, not a serial device";
  if (S_ISSOCK(info.st_mode)) return "a socket, not a serial device";
  if (!S_ISCHR(info.st_mode)) return "not a serial device";
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return std::string("cannot open it: ") + std::strerror(errno);
  const bool terminal = ::isatty(fd) == 1;
  ::close(fd);
  if (!terminal) return "a character device but not a terminal, so not a serial line";
  return {};
}

}  // namespace sculpt::tools
