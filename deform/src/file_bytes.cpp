#include "file_bytes.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

std::string errno_text(const char* what) {
  return std::string(what) + " (" + std::strerror(errno) + ")";
}

}  // namespace

std::string read_file_bytes(const std::string& path) {
  // A directory opens fine with fopen on Linux and only fails on read; say what it is instead.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw ModelFileError(path, "", "cannot read: is a directory");
  }
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) throw ModelFileError(path, "", errno_text("cannot open"));
  std::string bytes;
  // Grow by reading rather than trusting a size query, so pipes and special files work too;
  // for regular files the first reserve makes this a single read.
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) bytes.reserve(static_cast<std::size_t>(size));
  char chunk[1 << 16];
  for (;;) {
    const std::size_t got = std::fread(chunk, 1, sizeof chunk, file.get());
    bytes.append(chunk, got);
    if (got < sizeof chunk) break;
  }
  if (std::ferror(file.get())) throw ModelFileError(path, "", errno_text("cannot read"));
  return bytes;
}

}  // namespace sculpt::deform
