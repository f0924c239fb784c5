#include "sculpt/base/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sculpt::base {
namespace {

std::string errno_text(const char* what) { return std::string(what) + " (" + std::strerror(errno) + ")"; }

// What a path is when it is not a regular file, in the words `ls -l` users know.
const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return kCharacterDevice.data();
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Closes the descriptor on every way out of read_regular_file.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

}  // namespace

int open_regular_file(const std::string& path) {
  // O_NONBLOCK keeps the open itself from waiting for a FIFO's writer; fstat on the open
  // descriptor then says what the path is without the race a stat before the open would leave.
  Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (file.get() < 0) throw FileReadError(errno_text("cannot open"));
  struct stat info {};
  if (::fstat(file.get(), &info) != 0) throw FileReadError(errno_text("cannot read"));
  if (!S_ISREG(info.st_mode)) {
    throw FileReadError(std::string("cannot read: ") + kind_of(info.st_mode) + ", not a regular file");
  }
  // A regular file's reads never wait anyway; cleared so the descriptor is an ordinary one.
  const int flags = ::fcntl(file.get(), F_GETFL);
  if (flags < 0 || ::fcntl(file.get(), F_SETFL, flags & ~O_NONBLOCK) != 0) {
    throw FileReadError(errno_text("cannot read"));
  }
  return file.release();
}

std::string non_regular_kind(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || S_ISREG(info.st_mode)) return {};
  return kind_of(info.st_mode);
}

std::string read_regular_file(const std::string& path) {
  const Descriptor file(open_regular_file(path));
  std::string bytes;
  struct stat info {};
  if (::fstat(file.get(), &info) != 0) throw FileReadError(errno_text("cannot read"));
  bytes.reserve(static_cast<std::size_t>(info.st_size));
  // Read to the end rather than exactly st_size bytes: a file that grows or shrinks while it is
  // read is then read as it ends up, never past its end.
  char chunk[1 << 16];
  for (;;) {
    const ssize_t got = ::read(file.get(), chunk, sizeof chunk);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw FileReadError(errno_text("cannot read"));
    }
    if (got == 0) break;
    bytes.append(chunk, static_cast<std::size_t>(got));
  }
  return bytes;
}

}  // namespace sculpt::base
