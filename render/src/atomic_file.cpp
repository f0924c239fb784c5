#include "atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sculpt::render {
namespace {

[[noreturn]] void fail(const std::string& path, const char* what, int error) {
  throw std::runtime_error(path + ": " + what + ": " + std::strerror(error));
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view bytes) {
  // Same folder, so that rename() never crosses a file system (where it would not be atomic).
  std::string temporary = path + ".tmp-XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) fail(path, "cannot create a temporary file beside it", errno);
  auto abandon = [&](const char* what) {
    const int error = errno;
    close(fd);
    unlink(temporary.c_str());
    fail(path, what, error);
  };
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) abandon("cannot write");
    written += static_cast<std::size_t>(n);
  }
  if (fchmod(fd, 0644) != 0) abandon("cannot set permissions");
  if (fsync(fd) != 0) abandon("cannot flush to disk");
  if (close(fd) != 0) {
    const int error = errno;
    unlink(temporary.c_str());
    fail(path, "cannot close", error);
  }
  if (rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    unlink(temporary.c_str());
    fail(path, "cannot rename the temporary file into place", error);
  }
}

}  // namespace sculpt::render
