#include "sculpt/render/png_file.hpp"

#include <string>

// The one definition of stb_image_write's functions in the program.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC  // keep its symbols private to this library
#include <stb_image_write.h>

#include "sculpt/deform/atomic_file.hpp"

namespace sculpt::render {
namespace {

void append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw PngFileError(path + ": cannot write an empty picture");
  std::string bytes;
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.pixels.data(), image.width * 3)) {
    throw PngFileError(path + ": PNG encoding failed");
  }
  try {
    deform::write_file_atomically(path, bytes);
  } catch (const std::runtime_error& e) {
    throw PngFileError(e.what());
  }
}

}  // namespace sculpt::render
