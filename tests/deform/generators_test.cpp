#include "sculpt/deform/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace sculpt::deform {
namespace {

// Nearest-neighbour distance of every point, by brute force (independent of PointIndex).
std::vector<double> nearest_neighbour_distances(const PointModel& m) {
  std::vector<double> nn(m.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (std::size_t j = i + 1; j < m.size(); ++j) {
      const double d = norm(m.position(i) - m.position(j));
      nn[i] = std::min(nn[i], d);
      nn[j] = std::min(nn[j], d);
    }
  }
  return nn;
}

TEST(Generators, SphereDefaultsToTheThesisModel) {
  const PointModel m = make_sphere();
  EXPECT_EQ(m.size(), 3203u);
  EXPECT_TRUE(m.has_normals());
  EXPECT_FALSE(m.has_colors());
  EXPECT_TRUE(m.triangles.empty());
  EXPECT_NO_THROW(m.validate());
}

TEST(Generators, SpherePointsLieOnTheSphereWithOutwardNormals) {
  const Vec3 c{0.5, -2.0, 3.0};
  const double r = 2.5;
  const PointModel m = make_sphere(2000, r, c);
  ASSERT_EQ(m.size(), 2000u);
  Vec3 mean{};
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 d = m.position(i) - c;
    EXPECT_NEAR(norm(d), r, 1e-6 * r);
    const Vec3 n = m.normal(i);
    EXPECT_NEAR(norm(n), 1.0, 1e-6);
    EXPECT_GT(dot(n, normalized(d)), 1.0 - 1e-6);
    mean += d;
  }
  // Balanced: the points' centroid is the centre.
  EXPECT_LT(norm(mean * (1.0 / static_cast<double>(m.size()))), 1e-3 * r);
}

TEST(Generators, SphereIsNearUniform) {
  const PointModel m = make_sphere();
  const std::vector<double> nn = nearest_neighbour_distances(m);
  const auto [lo, hi] = std::minmax_element(nn.begin(), nn.end());
  EXPECT_GT(*lo / *hi, 0.5) << "min " << *lo << " max " << *hi;
  // Spacing matches the area per point: 4 pi r^2 / n is roughly (0.93 * spacing)^2 on a
  // hexagonal-ish lattice; accept a generous band around sqrt(area per point).
  const double per_point = std::sqrt(4.0 * std::acos(-1.0) / 3203.0);
  EXPECT_GT(*lo, 0.5 * per_point);
  EXPECT_LT(*hi, 1.5 * per_point);
  // Equal-area bands: each hemisphere holds half the points.
  const auto north = std::count_if(m.z.begin(), m.z.end(), [](float z) { return z > 0.0f; });
  EXPECT_NEAR(static_cast<double>(north), 3203.0 / 2.0, 1.0);
}

TEST(Generators, SphereSmallCounts) {
  EXPECT_TRUE(make_sphere(0).empty());
  const PointModel one = make_sphere(1, 2.0);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(norm(one.position(0)), 2.0, 1e-6);
  EXPECT_THROW(make_sphere(10, 0.0), std::invalid_argument);
  EXPECT_THROW(make_sphere(10, -1.0), std::invalid_argument);
}

TEST(Generators, PlanePatchIsACentredGrid) {
  const PointModel m = make_plane_patch(11, 0.1);
  ASSERT_EQ(m.size(), 121u);
  ASSERT_TRUE(m.has_normals());
  Vec3 mean{};
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_EQ(m.z[i], 0.0f);
    EXPECT_EQ(m.normal(i), (Vec3{0, 0, 1}));
    mean += m.position(i);
  }
  EXPECT_LT(norm(mean), 1e-5);
  EXPECT_NEAR(*std::max_element(m.x.begin(), m.x.end()), 0.5, 1e-6);
  EXPECT_NEAR(*std::min_element(m.y.begin(), m.y.end()), -0.5, 1e-6);
  for (const double d : nearest_neighbour_distances(m)) EXPECT_NEAR(d, 0.1, 1e-6);
  EXPECT_TRUE(make_plane_patch(0, 1.0).empty());
  EXPECT_THROW(make_plane_patch(3, 0.0), std::invalid_argument);
}

TEST(Generators, BoxSurfaceCountsAndPlacement) {
  const Vec3 size{1.0, 0.6, 0.4};
  const double spacing = 0.1;
  const PointModel m = make_box(size, spacing);
  // 10 x 6 x 4 intervals: lattice points minus the interior ones.
  EXPECT_EQ(m.size(), 11u * 7u * 5u - 9u * 5u * 3u);
  ASSERT_TRUE(m.has_normals());
  EXPECT_NO_THROW(m.validate());
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 p = m.position(i);
    int faces = 0;
    Vec3 expected{};
    for (int a = 0; a < 3; ++a) {
      const double half = 0.5 * size[a];
      ASSERT_LE(std::abs(p[a]), half + 1e-6);
      if (std::abs(std::abs(p[a]) - half) < 1e-6) {
        ++faces;
        expected[a] = p[a] > 0 ? 1.0 : -1.0;
      } else {
        // Off a face, the coordinate sits on the grid.
        const double steps = (p[a] + half) / spacing;
        EXPECT_NEAR(steps, std::round(steps), 1e-4);
      }
    }
    ASSERT_GE(faces, 1) << "point " << i << " is not on the surface";
    const Vec3 n = m.normal(i);
    EXPECT_NEAR(norm(n), 1.0, 1e-6);
    EXPECT_GT(dot(n, normalized(expected)), 1.0 - 1e-6) << "point " << i;
  }
}

TEST(Generators, BoxHasNoDuplicatePoints) {
  const PointModel m = make_box({0.7, 0.7, 0.3}, 0.05);
  std::vector<std::array<float, 3>> points;
  for (std::size_t i = 0; i < m.size(); ++i) points.push_back({m.x[i], m.y[i], m.z[i]});
  std::sort(points.begin(), points.end());
  EXPECT_EQ(std::adjacent_find(points.begin(), points.end()), points.end());
  // And the closest pair is a grid step apart, not a near-duplicate.
  const std::vector<double> nn = nearest_neighbour_distances(m);
  EXPECT_NEAR(*std::min_element(nn.begin(), nn.end()), 0.05, 1e-5);
}

TEST(Generators, BoxCornersAndEdges) {
  const PointModel m = make_box({2.0, 2.0, 2.0}, 1.0);  // 3 x 3 x 3 lattice: 26 points
  ASSERT_EQ(m.size(), 26u);
  int corners = 0, edges = 0, centres = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 p = m.position(i);
    const Vec3 n = m.normal(i);
    const int on = (p.x != 0) + (p.y != 0) + (p.z != 0);
    EXPECT_NEAR(dot(n, normalized(p)), 1.0, 1e-6);  // the box is a cube: normal along p
    corners += on == 3;
    edges += on == 2;
    centres += on == 1;
  }
  EXPECT_EQ(corners, 8);
  EXPECT_EQ(edges, 12);
  EXPECT_EQ(centres, 6);
}

TEST(Generators, BoxSpacingIsFittedToTheEdges) {
  // 1 / 0.3 rounds to 3 intervals of 1/3; a tiny edge still gets both faces.
  const PointModel m = make_box({1.0, 1.0, 0.01}, 0.3);
  EXPECT_EQ(m.size(), 4u * 4u * 2u);
  EXPECT_THROW(make_box({1.0, 0.0, 1.0}, 0.1), std::invalid_argument);
  EXPECT_THROW(make_box({1.0, 1.0, 1.0}, 0.0), std::invalid_argument);
}

TEST(Generators, ACountPastTheBudgetIsRefusedInPlainNumbers) {
  try {
    make_plane_patch(100000, 1.0);  // 1e10 points
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "generator: 1e+10 points requested, more than the 1e+09 a generator makes (a spacing or a count "
              "mistyped?)");
  }
  EXPECT_THROW(make_box({1.0, 1.0, 1.0}, 1e-4), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
