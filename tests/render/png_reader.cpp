// Built into render_tests through png_file_test.cpp, which includes this file: the test glob
// picks up only *_test.cpp files, and stb_image's implementation must be compiled exactly once.
#include "render/png_reader.hpp"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>

#include <algorithm>

namespace sculpt::test {

render::Image read_png(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  render::Image image;
  if (data == nullptr) return image;
  image.width = width;
  image.height = height;
  image.pixels.assign(data, data + static_cast<std::size_t>(width) * height * 3);
  stbi_image_free(data);
  return image;
}

}  // namespace sculpt::test
