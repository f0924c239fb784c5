#pragma once
// An 8-bit RGB picture in memory, top row first: what every view renders into and what the
// PNG writer takes.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sculpt::render {

/// A colour with channels in [0, 1].
struct Rgb {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
};

/// Rows top to bottom, pixels left to right, three bytes (r, g, b) each.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;

  Image() = default;
  /// A width x height picture filled with `fill`. Throws std::invalid_argument unless both
  /// sizes are positive.
  Image(int width, int height, const Rgb& fill);

  std::uint8_t* at(int x, int y) { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  const std::uint8_t* at(int x, int y) const { return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }

  /// Sets one pixel; outside the picture it does nothing, so callers may draw past the edges.
  void set(int x, int y, const Rgb& color);
  /// Fills the rectangle [x, x + w) x [y, y + h), clipped to the picture.
  void fill_rect(int x, int y, int w, int h, const Rgb& color);
  /// Copies `tile` with its top-left corner at (x, y), clipped to the picture.
  void paste(const Image& tile, int x, int y);
};

/// One channel in [0, 1] as a byte, rounded and clamped.
std::uint8_t to_byte(double channel);

}  // namespace sculpt::render
