#include "sculpt/deform/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

namespace fs = std::filesystem;

// Leftover temporary names must stay within NAME_MAX (255) next to a long target name, yet
// still show which file they were for.
constexpr std::size_t kMaxNameInTemp = 200;
constexpr int kMaxNameAttempts = 100;

[[noreturn]] void fail(const std::string& path, const std::string& problem, int error) {
  throw ModelFileError(path, "", problem + " (" + std::strerror(error) + ")");
}

// fail() for the call that just set errno; it is read before anything else can change it.
[[noreturn]] void fail_errno(const std::string& path, const char* problem) {
  const int error = errno;
  fail(path, problem, error);
}

// The file a write to `path` must replace: a symbolic link is followed, so writing to it
// updates what it points at instead of turning the link into a plain file.
fs::path resolve_target(const std::string& path) {
  std::error_code ec;
  if (!fs::is_symlink(fs::symlink_status(path, ec))) return fs::path(path);
  const fs::path resolved = fs::weakly_canonical(path, ec);
  if (ec) fail(path, "cannot follow the symbolic link", ec.value());
  return resolved;
}

// A name unique to this process and call, so two writers never share a temporary file. Not
// mkstemp: it creates the file 0600, and widening that to the usual 0666 & ~umask would need
// umask(), which changes the mask for every thread for a moment. open(O_EXCL) with mode 0666
// lets the kernel apply the umask, and an existing name (a crashed run's leftover) only costs
// another attempt.
std::string temporary_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = target.filename().string().substr(0, kMaxNameInTemp);
  return "." + name + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
}

// The temporary file, removed on every way out unless the rename took it.
class TemporaryFile {
 public:
  TemporaryFile(const fs::path& folder, const fs::path& target, const std::string& path) {
    for (int attempt = 0; attempt < kMaxNameAttempts; ++attempt) {
      name_ = (folder / temporary_name(target)).string();
      fd_ = ::open(name_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ >= 0) return;
      if (errno != EEXIST) break;
    }
    const int error = errno;
    fail(path, "cannot create a temporary file in " + folder.string(), error);
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!name_.empty()) ::unlink(name_.c_str());
  }

  int fd() const { return fd_; }
  const std::string& name() const { return name_; }

  /// Closes the descriptor, reporting the error a delayed write may only show here.
  int close() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result;
  }
  /// The rename took the file: nothing left to remove.
  void release() { name_.clear(); }

 private:
  std::string name_;
  int fd_ = -1;
};

void write_all(int fd, std::string_view bytes, const std::string& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail_errno(path, "cannot write");
    }
    done += static_cast<std::size_t>(n);
  }
}

// The rename is in the folder's entries; they reach the disk only when the folder is synced.
void sync_folder(const fs::path& folder, const std::string& path) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) fail_errno(path, "written, but its folder could not be opened to sync it");
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // Some file systems cannot sync a directory at all (EINVAL); the data itself is synced.
  if (result != 0 && error != EINVAL) fail(path, "written, but its folder could not be synced", error);
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view bytes) {
  const fs::path target = resolve_target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");

  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  if (exists) {
    if (!S_ISREG(existing.st_mode)) {
      throw ModelFileError(path, "",
                           S_ISDIR(existing.st_mode) ? "cannot write: is a directory"
                                                     : "cannot write: exists and is not a regular file");
    }
    // A rename needs only the folder's permission; without this check a read-only file the
    // user meant to protect would be replaced.
    if (::access(target.c_str(), W_OK) != 0) fail_errno(path, "cannot write");
  } else if (errno != ENOENT) {
    fail_errno(path, "cannot write");
  }

  TemporaryFile temporary(folder, target, path);
  write_all(temporary.fd(), bytes, path);
  if (exists && ::fchmod(temporary.fd(), existing.st_mode & 07777) != 0) {
    fail_errno(path, "cannot keep the file's permissions");
  }
  if (::fsync(temporary.fd()) != 0) fail_errno(path, "cannot write");
  if (temporary.close() != 0) fail_errno(path, "cannot write");
  if (::rename(temporary.name().c_str(), target.c_str()) != 0) fail_errno(path, "cannot replace");
  temporary.release();
  sync_folder(folder, path);
}

}  // namespace sculpt::deform
