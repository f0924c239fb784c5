// Depth-correct drawing: a near object hides a far one whatever order they are drawn in, and a
// model with faces is drawn as its faces, not as the dots of its corners.
#include <gtest/gtest.h>

#include "render/pinhole.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/render/view_renderer.hpp"

namespace sculpt::test {
namespace {

constexpr int kSize = 128;

deform::PointModel colored_sphere(double radius, const Vec3& centre, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  deform::PointModel m = deform::make_sphere(6000, radius, centre);
  m.resize(m.size(), true, true);
  std::fill(m.red.begin(), m.red.end(), r);
  std::fill(m.green.begin(), m.green.end(), g);
  std::fill(m.blue.begin(), m.blue.end(), b);
  return m;
}

deform::PointModel concatenated(const deform::PointModel& a, const deform::PointModel& b) {
  deform::PointModel m = a;
  for (std::size_t i = 0; i < b.size(); ++i) {
    m.push_back(b.position(i));
    m.set_normal(m.size() - 1, b.normal(i));
    m.red.back() = b.red[i];
    m.green.back() = b.green[i];
    m.blue.back() = b.blue[i];
  }
  return m;
}

bool reddish(const render::Image& image, const PixelPoint& p) {
  const std::uint8_t* c = image.at(static_cast<int>(p.x), static_cast<int>(p.y));
  return c[0] > 2 * c[1] + 10 && c[0] > 2 * c[2] + 10;
}
bool greenish(const render::Image& image, const PixelPoint& p) {
  const std::uint8_t* c = image.at(static_cast<int>(p.x), static_cast<int>(p.y));
  return c[1] > 2 * c[0] + 10 && c[1] > 2 * c[2] + 10;
}

TEST(Depth, ANearObjectOccludesAFarOneInEitherDrawingOrder) {
  // Seen from +z: a small red sphere in front of a large green one, offset so both show.
  const deform::PointModel near = colored_sphere(0.3, {0.2, 0.1, 0.8}, 230, 40, 40);
  const deform::PointModel far = colored_sphere(0.8, {0.0, 0.0, -0.5}, 40, 230, 40);
  render::Camera camera;
  camera.eye = {0.0, 0.0, 4.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.up = {0.0, 1.0, 0.0};
  camera.near_distance = 1.0;
  camera.far_distance = 8.0;
  camera.width = camera.height = kSize;
  render::ViewRenderer renderer(kSize, kSize);
  // Near first: without the depth test the far sphere, drawn later, would paint over it.
  for (const bool near_first : {true, false}) {
    const render::RenderModel both(near_first ? concatenated(near, far) : concatenated(far, near));
    const render::Image image = renderer.render(both, camera);
    EXPECT_TRUE(reddish(image, project(camera, {0.2, 0.1, 0.8}))) << "near sphere's centre, near first " << near_first;
    EXPECT_TRUE(reddish(image, project(camera, {0.2, 0.1 + 0.2, 0.8}))) << "inside the near disc";
    EXPECT_TRUE(greenish(image, project(camera, {-0.5, -0.3, -0.5 + 0.55}))) << "far sphere beside the near one";
  }
}

TEST(Depth, FacesAreFilledWhereSplatsWouldLeaveGaps) {
  // A square of two triangles with points only at its corners: as splats it would be four dots.
  deform::PointModel square;
  for (const Vec3 p : {Vec3{-1, -1, 0}, Vec3{1, -1, 0}, Vec3{1, 1, 0}, Vec3{-1, 1, 0}}) square.push_back(p);
  square.triangles = {0, 1, 2, 0, 2, 3};
  const render::RenderModel model(square);
  ASSERT_TRUE(model.has_faces());
  render::Lighting lighting;
  lighting.background = {0.0, 0.0, 0.0};
  const render::Camera camera =
      render::fit_camera({0, 0, 0}, std::sqrt(2.0), {0, 0, -1}, render::UpAxis::kY, kSize, kSize);
  const render::Image image = render::ViewRenderer(kSize, kSize).render(model, camera, lighting);
  const PixelPoint inner = project(camera, {0.5, -0.3, 0.0});
  EXPECT_GT(luminance(image, static_cast<int>(inner.x), static_cast<int>(inner.y)), 100.0);
  const PixelPoint outer = project(camera, {1.2, 0.0, 0.0});
  EXPECT_EQ(luminance(image, static_cast<int>(outer.x), static_cast<int>(outer.y)), 0.0);
}

}  // namespace
}  // namespace sculpt::test
