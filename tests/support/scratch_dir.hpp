#pragma once
// A folder of the test process's own under the system's temporary folder, removed with all it
// holds when the process exits: test runs leave nothing behind in /tmp, and parallel ctest
// processes (one per test) never share a folder.

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace sculpt::test {

class ScratchDir {
 public:
  /// `prefix` names the test file; the process id keeps processes apart. Made on construction.
  explicit ScratchDir(const std::string& prefix)
      : path_(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;  // a destructor at exit has no one to tell
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace sculpt::test
