// The colour bar's ticks and the labels' font.
#include <gtest/gtest.h>

#include "sculpt/render/color_bar.hpp"
#include "sculpt/render/text.hpp"

namespace sculpt::test {
namespace {

void expect_ticks(double max, const std::vector<double>& expected) {
  const std::vector<double> ticks = render::color_bar_ticks(max);
  ASSERT_EQ(ticks.size(), expected.size()) << "max " << max;
  for (std::size_t i = 0; i < ticks.size(); ++i) EXPECT_NEAR(ticks[i], expected[i], 1e-12) << "max " << max;
}

TEST(ColorBar, TicksAreRoundStepsUpToTheMaximum) {
  expect_ticks(0.0816, {0.0, 0.02, 0.04, 0.06, 0.08});
  expect_ticks(1.0, {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
  expect_ticks(37.0, {0.0, 10.0, 20.0, 30.0});
  expect_ticks(0.0, {0.0});  // nothing moved
}

TEST(ColorBar, DrawsTheScaleWithinItsWidth) {
  const render::ColorBar bar{0.5, "displacement", "model units", 1};
  const int width = render::color_bar_width(bar);
  render::Image image(width + 20, 200, {1, 1, 1});
  render::draw_color_bar(image, 0, 0, 200, bar);
  for (int y = 0; y < image.height; ++y) {
    for (int x = width; x < image.width; ++x) ASSERT_EQ(image.at(x, y)[0], 255) << x << "," << y;
  }
}

TEST(Text, InkStaysInTheBoxTheFontMeasures) {
  render::Image image(100, 40, {1, 1, 1});
  render::draw_text(image, 10, 5, "0.08", {0, 0, 0}, 2);
  const int w = render::text_width("0.08", 2), h = render::text_height("0.08", 2);
  int ink = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (image.at(x, y)[0] == 255) continue;
      ++ink;
      EXPECT_TRUE(x >= 10 && x < 10 + w && y >= 5 && y < 5 + h) << x << "," << y;
    }
  }
  EXPECT_GT(ink, 40);
}

}  // namespace
}  // namespace sculpt::test
