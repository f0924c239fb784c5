#pragma once
// A file's bytes as a test reads them back: what a command, a log or a writer left on disk.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sculpt::test {

/// Every byte of the file at `path`; empty when it cannot be opened.
inline std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace sculpt::test
