#pragma once
// Labels drawn straight into an image with stb_easy_font's bitmap-like segment font (ASCII
// only), scaled by whole pixels so the strokes stay crisp.

#include <string_view>

#include "sculpt/render/image.hpp"

namespace sculpt::render {

/// Draws `text` with its top-left corner at (x, y); each font unit is `scale` pixels.
void draw_text(Image& image, int x, int y, std::string_view text, const Rgb& color, int scale = 2);
/// Width and height in pixels that draw_text covers for `text` at `scale`.
int text_width(std::string_view text, int scale = 2);
int text_height(std::string_view text, int scale = 2);

}  // namespace sculpt::render
