#pragma once
// Whole-file reads for the model readers, reporting failures as ModelFileError so callers see
// one exception type for everything file-related. Writes go through atomic_file.hpp.

#include <string>

namespace sculpt::deform {

/// The complete contents of a regular file. Throws ModelFileError when it cannot be read or is
/// not a regular file (a directory, FIFO or device is refused before anything is read).
std::string read_file_bytes(const std::string& path);

}  // namespace sculpt::deform
