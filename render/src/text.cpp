#include "sculpt/render/text.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

// stb_easy_font is a header of static functions: this file is its only user.
#include <stb_easy_font.h>

namespace sculpt::render {
namespace {

// stb_easy_font writes 4 vertices of 16 bytes (x, y, z floats and an RGBA byte colour) per
// quad; its own examples budget about 270 bytes a character.
constexpr std::size_t kVertexBytesPerChar = 300;

struct Quads {
  std::vector<char> vertices;
  int count = 0;
};

Quads layout(std::string_view text) {
  std::string copy(text);  // stb_easy_font takes a char*
  Quads q;
  q.vertices.resize(kVertexBytesPerChar * (copy.size() + 1));
  q.count =
      stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, q.vertices.data(), static_cast<int>(q.vertices.size()));
  return q;
}

}  // namespace

void draw_text(Image& image, int x, int y, std::string_view text, const Rgb& color, int scale) {
  const Quads q = layout(text);
  for (int i = 0; i < q.count; ++i) {
    // The quads are axis-aligned rectangles: corners 0 and 2 are opposite.
    float corner[2][2];
    for (int k = 0; k < 2; ++k) std::memcpy(corner[k], q.vertices.data() + (4 * i + 2 * k) * 16, sizeof corner[k]);
    const int x0 = static_cast<int>(std::lround(std::fmin(corner[0][0], corner[1][0]) * scale));
    const int x1 = static_cast<int>(std::lround(std::fmax(corner[0][0], corner[1][0]) * scale));
    const int y0 = static_cast<int>(std::lround(std::fmin(corner[0][1], corner[1][1]) * scale));
    const int y1 = static_cast<int>(std::lround(std::fmax(corner[0][1], corner[1][1]) * scale));
    image.fill_rect(x + x0, y + y0, x1 - x0, y1 - y0, color);
  }
}

int text_width(std::string_view text, int scale) {
  std::string copy(text);
  return stb_easy_font_width(copy.data()) * scale;
}

int text_height(std::string_view text, int scale) {
  std::string copy(text);
  return stb_easy_font_height(copy.data()) * scale;
}

}  // namespace sculpt::render
