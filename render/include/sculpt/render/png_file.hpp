#pragma once
// Pictures to PNG files.

#include <stdexcept>
#include <string>

#include "sculpt/render/image.hpp"

namespace sculpt::render {

/// A PNG that could not be encoded or written; what() names the path and the reason.
class PngFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes `image` as an 8-bit RGB PNG, atomically: readers of `path` see the old file or the
/// whole new one, never half a picture (a temporary file in the same folder, then rename).
void write_png(const std::string& path, const Image& image);

}  // namespace sculpt::render
