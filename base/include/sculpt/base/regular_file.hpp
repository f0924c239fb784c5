#pragma once
// Whole-file reads of what must be a regular file (a model, a scene): a directory, FIFO or
// device is refused before anything is read, since /dev/zero never ends and a FIFO waits for
// a writer. Each reader wraps the reason into its own error type, which names the file.

#include <stdexcept>
#include <string>

namespace sculpt::base {

/// Why a file could not be read, without its path ("cannot read: a FIFO, not a regular file").
class FileReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The complete contents of the regular file at `path`. Throws FileReadError when it cannot be
/// opened or read, or is not a regular file.
std::string read_regular_file(const std::string& path);

}  // namespace sculpt::base
