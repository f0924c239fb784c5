#include "sculpt/render/color_bar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sculpt/render/heat_map.hpp"
#include "sculpt/render/text.hpp"

namespace sculpt::render {
namespace {

constexpr Rgb kInk{0.12, 0.12, 0.14};

// The smallest step of 1, 2 or 5 times a power of ten that is at least `raw`.
double round_step(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * power >= raw * (1.0 - 1e-12)) return m * power;
  }
  return 10.0 * power;
}

std::string label(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

std::vector<double> color_bar_ticks(double max, int most) {
  if (!(max > 0.0) || !std::isfinite(max) || most < 2) return {0.0};
  const double step = round_step(max / (most - 1));
  std::vector<double> ticks;
  for (int i = 0; i * step <= max * (1.0 + 1e-9); ++i) ticks.push_back(i * step);
  return ticks;
}

namespace {

struct BarLayout {
  int pad, line, strip, tick;
};

BarLayout layout(const ColorBar& bar) {
  const int scale = bar.text_scale;
  return {4 * scale, text_height("0", scale), 10 * scale, 3 * scale};
}

std::string max_label(const ColorBar& bar) { return "max " + label(bar.max); }

}  // namespace

int color_bar_width(const ColorBar& bar) {
  const BarLayout l = layout(bar);
  int labels = 0;
  for (const double tick : color_bar_ticks(bar.max)) labels = std::max(labels, text_width(label(tick), bar.text_scale));
  const int texts = std::max({text_width(bar.title, bar.text_scale), text_width(bar.unit, bar.text_scale),
                              text_width(max_label(bar), bar.text_scale), l.strip + l.tick + l.pad + labels});
  return texts + 2 * l.pad;
}

void draw_color_bar(Image& image, int x, int y, int h, const ColorBar& bar) {
  const BarLayout l = layout(bar);
  const int scale = bar.text_scale;
  const int strip_top = y + l.pad + l.line;
  const int strip_height = std::max(8, h - 3 * l.pad - 3 * l.line);
  const int strip_x = x + l.pad;
  draw_text(image, x + l.pad, y, bar.title, kInk, scale);
  for (int row = 0; row < strip_height; ++row) {
    const double t = 1.0 - static_cast<double>(row) / std::max(1, strip_height - 1);
    image.fill_rect(strip_x, strip_top + row, l.strip, 1, heat_color(t));
  }
  const double top = bar.max > 0.0 ? bar.max : 1.0;  // nothing moved: the single tick 0 at the bottom
  for (const double tick : color_bar_ticks(bar.max)) {
    const int row = strip_top + static_cast<int>(std::lround((1.0 - tick / top) * (strip_height - 1)));
    image.fill_rect(strip_x + l.strip, row, l.tick, scale, kInk);
    // stb_easy_font's digits sit in the upper part of their line box.
    draw_text(image, strip_x + l.strip + l.tick + l.pad, row - l.line / 4, label(tick), kInk, scale);
  }
  // Below the 0 tick's label, which hangs a little under the strip.
  const int below = strip_top + strip_height + 2 * l.pad;
  draw_text(image, x + l.pad, below, bar.unit, kInk, scale);
  draw_text(image, x + l.pad, below + l.line, max_label(bar), kInk, scale);
}

}  // namespace sculpt::render
