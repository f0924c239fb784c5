#pragma once
// Reading a PNG back for tests that check pictures by their content (stb_image).

#include <string>

#include "sculpt/render/image.hpp"

namespace sculpt::test {

/// The PNG at `path` as RGB; an empty image (width 0) when it cannot be read.
render::Image read_png(const std::string& path);

}  // namespace sculpt::test
