#pragma once
// Whole-file reads for the model readers, reporting failures as ModelFileError so callers see
// one exception type for everything file-related. Writes go through atomic_file.hpp.

#include <string>

namespace sculpt::deform {

/// The complete contents of a regular file. Throws ModelFileError when it cannot be read.
std::string read_file_bytes(const std::string& path);

}  // namespace sculpt::deform
