#pragma once
// Whole-file reads and writes for the model readers and writers, reporting failures as
// ModelFileError so callers see one exception type for everything file-related.

#include <string>
#include <string_view>

namespace sculpt::deform {

/// The complete contents of a regular file. Throws ModelFileError when it cannot be read.
std::string read_file_bytes(const std::string& path);
/// Replaces the file's contents with `bytes`. Throws ModelFileError when it cannot be written.
void write_file_bytes(const std::string& path, std::string_view bytes);

}  // namespace sculpt::deform
