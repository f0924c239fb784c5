// RenderModel::follow, what a live view calls for each frame: the drawn copy takes the moved
// points and normals exactly as a fresh build of the moved model would, keeps its colours, and
// sizes each splat again from the neighbours it had at the build: as a fresh build does where
// the model only grew, wider where a move opened a gap, the same where nothing near moved.
#include "sculpt/render/render_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_scale.hpp"
#include "sculpt/deform/point_index.hpp"

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

// Each point's splat diameter (0 for a point in no class).
std::vector<double> diameters(const RenderModel& m) {
  std::vector<double> d(m.size(), 0.0);
  for (const SplatClass& c : m.splat_classes()) {
    for (const std::uint32_t i : c.points) d[i] = c.diameter;
  }
  return d;
}

TEST(RenderModel, FollowTakesTheMovedPointsAndNormalsAndKeepsColours) {
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
  ASSERT_FALSE(same_classes(fresh.splat_classes(), built_classes)) << "the stretch must change the splat sizes";
  EXPECT_FALSE(same_classes(drawn.splat_classes(), built_classes)) << "follow kept the splats of before the stretch";

  // Without normals of its own the moved model's are estimated, as a build estimates them.
  deform::PointModel bare = moved;
  bare.nx.clear();
  bare.ny.clear();
  bare.nz.clear();
  drawn.follow(bare);
  EXPECT_EQ(drawn.normals(), RenderModel(bare).normals());
  EXPECT_EQ(drawn.positions(), fresh.positions());
}

// Twice as large in every direction: the same neighbours, each twice as far, and the spacing
// one octave (four classes) up, exactly what a fresh build of the larger model measures.
TEST(RenderModel, FollowSizesTheSplatsOfAModelTwiceAsLargeAsAFreshBuildDoes) {
  const deform::PointModel sphere = deform::make_sphere(2000);
  RenderModel drawn(sphere);
  deform::PointModel doubled = sphere;
  for (std::size_t i = 0; i < doubled.size(); ++i) {
    doubled.x[i] *= 2.0f;
    doubled.y[i] *= 2.0f;
    doubled.z[i] *= 2.0f;
  }
  const std::vector<double> before = diameters(drawn);
  drawn.follow(doubled);
  const std::vector<double> after = diameters(drawn), fresh = diameters(RenderModel(doubled));
  for (std::size_t i = 0; i < after.size(); ++i) {
    ASSERT_GT(before[i], 0.0) << i;
    ASSERT_NEAR(after[i], fresh[i], 1e-12 * fresh[i]) << "point " << i;
    ASSERT_NEAR(after[i], 2.0 * before[i], 1e-12 * after[i]) << "point " << i;
  }
}

// The sphere's upper half lifted by three typical spacings: the points by the cut, whose
// neighbours at the build lay across it, get wider splats; a point farther than three spacings
// from the cut (its three nearest are within two) keeps its own, and no splat narrows.
TEST(RenderModel, FollowWidensTheSplatsWhereAMoveOpensAGapAndKeepsTheRest) {
  const deform::PointModel sphere = deform::make_sphere(2000);
  const double spacing = deform::typical_spacing(sphere, deform::PointIndex(sphere)).value;
  RenderModel drawn(sphere);
  const std::vector<double> before = diameters(drawn);
  deform::PointModel lifted = sphere;
  for (std::size_t i = 0; i < lifted.size(); ++i) {
    if (lifted.z[i] > 0.0f) lifted.z[i] += static_cast<float>(3.0 * spacing);
  }
  drawn.follow(lifted);
  const std::vector<double> after = diameters(drawn);
  std::size_t far = 0, widened = 0;
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_GE(after[i], before[i]) << "point " << i;
    if (std::abs(sphere.z[i]) > 3.0 * spacing) {
      ++far;
      EXPECT_EQ(after[i], before[i]) << "point " << i << " at z " << sphere.z[i];
    }
    widened += after[i] > before[i];
  }
  EXPECT_GT(far, sphere.size() / 2);
  // The band of points within a spacing or so of the cut: tens on a 2,000-point sphere.
  EXPECT_GE(widened, 20u);
  std::printf("[ render ] lifted half: %zu of %zu splats widened, %zu far from the cut kept\n", widened, sphere.size(),
              far);
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
