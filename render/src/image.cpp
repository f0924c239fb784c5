#include "sculpt/render/image.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sculpt::render {

std::uint8_t to_byte(double channel) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(channel, 0.0, 1.0) * 255.0));
}

Image::Image(int w, int h, const Rgb& fill) : width(w), height(h) {
  if (w <= 0 || h <= 0) {
    throw std::invalid_argument("image size " + std::to_string(w) + "x" + std::to_string(h) + " is not positive");
  }
  pixels.resize(static_cast<std::size_t>(w) * h * 3);
  fill_rect(0, 0, w, h, fill);
}

void Image::set(int x, int y, const Rgb& color) {
  if (!contains(x, y)) return;
  std::uint8_t* p = at(x, y);
  p[0] = to_byte(color.r);
  p[1] = to_byte(color.g);
  p[2] = to_byte(color.b);
}

void Image::fill_rect(int x, int y, int w, int h, const Rgb& color) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0);
  const int x1 = std::min(x + w, width), y1 = std::min(y + h, height);
  const std::uint8_t rgb[3] = {to_byte(color.r), to_byte(color.g), to_byte(color.b)};
  for (int row = y0; row < y1; ++row) {
    for (int col = x0; col < x1; ++col) std::copy(rgb, rgb + 3, at(col, row));
  }
}

void Image::paste(const Image& tile, int x, int y) {
  const int x0 = std::max(x, 0), x1 = std::min(x + tile.width, width);
  if (x0 >= x1) return;
  for (int row = std::max(y, 0); row < std::min(y + tile.height, height); ++row) {
    const std::uint8_t* from = tile.at(x0 - x, row - y);
    std::copy(from, from + 3 * (x1 - x0), at(x0, row));
  }
}

}  // namespace sculpt::render
