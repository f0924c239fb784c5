// A picture's size is known before it is drawn, and a request past kMaxPicturePixels is refused
// then: `sculpt render --views 36 --size 4000x4000` asked for a 1.7 GB picture.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "sculpt/deform/generators.hpp"
#include "sculpt/render/picture.hpp"

namespace sculpt::test {
namespace {

render::PictureRequest request_of(int views, int width, int height) {
  render::PictureRequest r;
  r.views = views;
  r.view_width = width;
  r.view_height = height;
  return r;
}

// The size told beforehand is the size drawn: every layout (one view or a row, with or without
// the model before), read off the picture render_picture returns.
TEST(PictureSize, TheGridToldBeforehandIsTheGridDrawn) {
  const deform::PointModel before = deform::make_sphere(200, 1.0);
  deform::PointModel after = before;
  after.set_position(0, after.position(0) * 0.9);
  for (const int views : {1, 3}) {
    for (const bool compare : {false, true}) {
      const render::PictureRequest r = request_of(views, 40, 30);
      render::PictureInfo info;
      const render::Image picture = render::render_picture(after, compare ? &before : nullptr, r, &info);
      const long long drawn = static_cast<long long>(info.columns) * r.view_width * picture.height;
      EXPECT_EQ(picture.height, info.rows * r.view_height) << views << " views, compare " << compare;
      EXPECT_EQ(render::picture_grid_pixels(r, compare), drawn) << views << " views, compare " << compare;
      // Without a colour bar the grid is the whole picture.
      if (!compare) {
        EXPECT_EQ(static_cast<long long>(picture.width) * picture.height, drawn);
      }
    }
  }
}

TEST(PictureSize, APictureUpToTheLimitPassesAndOnePastItIsRefusedNamingBoth) {
  // 8000 x 8000 is the limit exactly; one row more is past it.
  EXPECT_NO_THROW(render::check_picture_request(request_of(1, 8000, 8000), false));
  try {
    render::check_picture_request(request_of(1, 8000, 8001), false);
    FAIL() << "a picture past the limit was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("1 x 1 views of 8000x8001 make 64 million pixels"), std::string::npos) << message;
    EXPECT_NE(message.find("at most 64 million"), std::string::npos) << message;
  }
  // Comparing doubles the grid: a size that fits alone does not fit beside its before.
  EXPECT_NO_THROW(render::check_picture_request(request_of(1, 6000, 6000), false));
  EXPECT_THROW(render::check_picture_request(request_of(1, 6000, 6000), true), std::invalid_argument);
  // The report that found it.
  EXPECT_THROW(render::check_picture_request(request_of(36, 4000, 4000), false), std::invalid_argument);
  // And render_picture itself refuses before drawing.
  const deform::PointModel sphere = deform::make_sphere(50, 1.0);
  EXPECT_THROW(render::render_picture(sphere, nullptr, request_of(36, 4000, 4000)), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::test
