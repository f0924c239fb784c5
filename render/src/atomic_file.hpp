#pragma once
// Replacing a file all at once.
//
// A local helper for now: a shared atomic-write utility is being added to deform, and this one
// should give way to it once it lands.

#include <string>
#include <string_view>

namespace sculpt::render {

/// Writes `bytes` to a temporary file in `path`'s folder, flushes it to disk and renames it over
/// `path`, so that `path` is either the old file or the complete new one. The file is readable
/// by all (0644), as an ordinary write would leave it under the usual umask.
/// Throws std::runtime_error "<path>: <what failed>: <strerror>"; no temporary file is left.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace sculpt::render
