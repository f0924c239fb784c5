// RenderModel::follow, what a live view calls for each frame: the drawn copy takes the moved
// points and normals exactly as a fresh build of the moved model would, and keeps its colours
// and the splat sizes measured when it was built.
#include "sculpt/render/render_model.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/deform/generators.hpp"

namespace sculpt::render {
namespace {

// The sphere stretched to 1.5 times its width along x, its normals carried by the inverse
// transpose: more than two splat classes (19 % apart) of new spacing where it stretched most.
deform::PointModel stretched(const deform::PointModel& sphere) {
  deform::PointModel moved = sphere;
  for (std::size_t i = 0; i < moved.size(); ++i) {
    moved.x[i] *= 1.5f;
    moved.nx[i] /= 1.5f;
  }
  return moved;
}

bool same_classes(const std::vector<SplatClass>& a, const std::vector<SplatClass>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t c = 0; c < a.size(); ++c) {
    if (a[c].diameter != b[c].diameter || a[c].points != b[c].points) return false;
  }
  return true;
}

TEST(RenderModel, FollowTakesTheMovedPointsAndNormalsAndKeepsColoursAndSplats) {
  const deform::PointModel sphere = deform::make_sphere(2000);
  RenderModel drawn(sphere);
  const std::vector<SplatClass> built_classes = drawn.splat_classes();
  std::vector<Rgb> heat(sphere.size());
  for (std::size_t i = 0; i < heat.size(); ++i) heat[i] = {static_cast<double>(i % 7) / 7.0, 0.5, 0.25};
  drawn.set_colors(heat);
  const std::vector<float> colours = drawn.colors();

  const deform::PointModel moved = stretched(sphere);
  drawn.follow(moved);
  const RenderModel fresh(moved);
  EXPECT_EQ(drawn.positions(), fresh.positions());
  EXPECT_EQ(drawn.normals(), fresh.normals());
  EXPECT_EQ(drawn.colors(), colours);
  EXPECT_TRUE(same_classes(drawn.splat_classes(), built_classes));
  ASSERT_FALSE(same_classes(fresh.splat_classes(), built_classes)) << "the stretch must change the splat sizes";

  // Without normals of its own the moved model's are estimated, as a build estimates them.
  deform::PointModel bare = moved;
  bare.nx.clear();
  bare.ny.clear();
  bare.nz.clear();
  drawn.follow(bare);
  EXPECT_EQ(drawn.normals(), RenderModel(bare).normals());
  EXPECT_EQ(drawn.positions(), fresh.positions());
}

TEST(RenderModel, FollowRefusesAModelOfAnotherSize) {
  RenderModel drawn(deform::make_sphere(500));
  try {
    drawn.follow(deform::make_sphere(400));
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("400"), std::string::npos) << what;
    EXPECT_NE(what.find("500"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace sculpt::render
