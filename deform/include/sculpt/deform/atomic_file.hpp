#pragma once
// Writing a file whole or not at all: the bytes go to a temporary file beside the target, are
// flushed to the disk, and only then renamed over it, so a full disk, a crash or a power cut
// leaves either the old file or the new one, never a truncated mix.

#include <string>
#include <string_view>

namespace sculpt::deform {

/// Replaces (or creates) the file at `path` with `bytes`, atomically: a temporary file in the
/// same folder is written, fsync'ed, renamed over `path`, and the folder fsync'ed so the rename
/// itself survives a power cut. On any failure the temporary file is removed and `path` is as
/// it was. A symbolic link is written through (its target is replaced, the link kept); an
/// existing file keeps its permission bits, a new one gets 0666 less the umask. Refuses a path
/// that exists and is not a regular file (a directory, device or FIFO), and an existing file
/// the caller may not write. Throws ModelFileError naming `path` and the system's reason.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace sculpt::deform
