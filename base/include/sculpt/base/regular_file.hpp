#pragma once
// Whole-file reads of what must be a regular file (a model, a scene): a directory, FIFO or
// device is refused before anything is read, since /dev/zero never ends and a FIFO waits for
// a writer. Each reader wraps the reason into its own error type, which names the file.

#include <stdexcept>
#include <string>
#include <string_view>

namespace sculpt::base {

/// Why a file could not be read, without its path ("cannot read: a FIFO, not a regular file").
class FileReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The complete contents of the regular file at `path`. Throws FileReadError when it cannot be
/// opened or read, or is not a regular file.
std::string read_regular_file(const std::string& path);

/// A descriptor open for blocking reads (close-on-exec) of the regular file at `path`, for a
/// reader that streams the file (an event log) rather than taking it whole; the caller closes
/// it. Throws FileReadError as read_regular_file does ("cannot read: a FIFO, not a regular
/// file"): the open never waits for a FIFO's writer.
int open_regular_file(const std::string& path);

/// What non_regular_kind() says of a character device (/dev/null), which a log may be.
inline constexpr std::string_view kCharacterDevice = "a character device";

/// What the existing path is when it is not a regular file ("a directory", "a FIFO", "a
/// character device", ...); empty when it is one, or when it cannot be looked up (a file yet
/// to be made).
std::string non_regular_kind(const std::string& path);

}  // namespace sculpt::base
