#pragma once
// The legend of a heat map: the scale from 0 to the largest value, with ticks labelled in the
// model's own units.

#include <string>
#include <vector>

#include "sculpt/render/image.hpp"

namespace sculpt::render {

/// Round tick values from 0 to at most `max` (steps of 1, 2 or 5 times a power of ten, at most
/// `most` ticks), ending with `max` itself when the last round tick falls short of it.
std::vector<double> color_bar_ticks(double max, int most = 6);

/// What a colour bar shows.
struct ColorBar {
  double max = 0.0;    ///< the value at the top (0 at the bottom)
  std::string title;   ///< above the bar
  std::string unit;    ///< below it, then "max <value>"
  int text_scale = 2;  ///< pixels per font unit
};

/// The width draw_color_bar needs for `bar`'s texts and labels.
int color_bar_width(const ColorBar& bar);

/// Draws `bar` vertically in the rectangle (x, y, color_bar_width(bar), h): the title on top,
/// the heat scale with labelled ticks, the unit and the largest value underneath.
void draw_color_bar(Image& image, int x, int y, int h, const ColorBar& bar);

}  // namespace sculpt::render
