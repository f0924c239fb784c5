// Z order (spatial_order.hpp): a permutation, the defining property of Z order checked on a
// grid without its bit arithmetic, every attribute and triangle kept, locality that rises, and
// frames on the reordered model moving the same points the same way.
#include "sculpt/deform/spatial_order.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sphere_settings.hpp"

namespace sculpt::deform {
namespace {

bool is_permutation_of_size(const std::vector<std::uint32_t>& order, std::size_t n) {
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> expected(n);
  std::iota(expected.begin(), expected.end(), 0u);
  return sorted == expected;
}

TEST(SpatialOrder, IsAPermutationAndTheSameEveryTime) {
  const PointModel sphere = make_sphere(3203);
  const std::vector<std::uint32_t> order = spatial_order(sphere);
  EXPECT_TRUE(is_permutation_of_size(order, sphere.size()));
  EXPECT_EQ(order, spatial_order(sphere));
  // Coincident points (same cell) come in index order; a model of one repeated point keeps its order.
  PointModel same;
  for (int i = 0; i < 5; ++i) same.push_back({0.5, 0.5, 0.5});
  EXPECT_EQ(spatial_order(same), (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(spatial_order(PointModel{}).empty());
}

// What makes Z order local, stated without interleaving bits: on an 8x8x8 grid, the points of
// every aligned 2x2x2 block, and of every aligned 4x4x4 block, are stored one after another.
TEST(SpatialOrder, EveryAlignedBlockOfAGridIsStoredTogether) {
  std::vector<std::array<int, 3>> cells;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 8; ++z) cells.push_back({x, y, z});
  std::mt19937 rng(7);
  std::shuffle(cells.begin(), cells.end(), rng);
  PointModel grid;
  for (const auto& c : cells) grid.push_back({0.25 + c[0], 0.25 + c[1], 0.25 + c[2]});
  const std::vector<std::uint32_t> order = spatial_order(grid);
  ASSERT_TRUE(is_permutation_of_size(order, grid.size()));
  for (const int block : {2, 4}) {
    const std::size_t per_block = static_cast<std::size_t>(block * block * block);
    for (std::size_t start = 0; start < order.size(); start += per_block) {
      std::set<std::array<int, 3>> blocks;
      for (std::size_t k = start; k < start + per_block; ++k) {
        const auto& c = cells[order[k]];
        blocks.insert({c[0] / block, c[1] / block, c[2] / block});
      }
      EXPECT_EQ(blocks.size(), 1u) << "places " << start << ".." << start + per_block - 1 << " span " << blocks.size()
                                   << " blocks of " << block;
    }
  }
}

TEST(SpatialOrder, ReorderingMovesEveryAttributeWithItsPointAndKeepsTheTriangles) {
  PointModel m = make_sphere(200);
  m.resize(m.size(), true, true, true);
  for (std::size_t i = 0; i < m.size(); ++i) {
    m.red[i] = static_cast<std::uint8_t>(i);
    m.green[i] = static_cast<std::uint8_t>(i / 3);
    m.blue[i] = static_cast<std::uint8_t>(i * 7);
    m.alpha[i] = static_cast<std::uint8_t>(255 - i);
  }
  for (std::uint32_t i = 0; i + 2 < m.size(); i += 3) m.triangles.insert(m.triangles.end(), {i, i + 1, i + 2});
  std::vector<std::uint32_t> order(m.size());
  std::iota(order.begin(), order.end(), 0u);
  std::mt19937 rng(3);
  std::shuffle(order.begin(), order.end(), rng);
  const PointModel r = reordered(m, order);
  ASSERT_EQ(r.size(), m.size());
  for (std::size_t k = 0; k < r.size(); ++k) {
    const std::size_t i = order[k];
    EXPECT_EQ(r.position(k), m.position(i));
    EXPECT_EQ(r.normal(k), m.normal(i));
    const std::array<int, 4> kept{r.red[k], r.green[k], r.blue[k], r.alpha[k]};
    const std::array<int, 4> given{m.red[i], m.green[i], m.blue[i], m.alpha[i]};
    EXPECT_EQ(kept, given);
  }
  // Each triangle still joins the same three positions, in the same turn.
  ASSERT_EQ(r.triangles.size(), m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    EXPECT_EQ(r.position(r.triangles[t]), m.position(m.triangles[t]));
  EXPECT_NO_THROW(r.validate());
}

TEST(SpatialOrder, RefusesAnOrderThatIsNotAPermutation) {
  const PointModel m = make_sphere(10);
  const auto message = [&](std::vector<std::uint32_t> order) {
    try {
      (void)reordered(m, order);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({0, 1, 2}), "reordered: the order has 3 entries for 10 points");
  EXPECT_EQ(message({0, 1, 2, 3, 4, 5, 6, 7, 8, 8}), "reordered: entry 9 (8) repeats a point");
  EXPECT_EQ(message({0, 1, 2, 3, 4, 5, 6, 7, 8, 10}), "reordered: entry 9 (10) is not a point");
}

// The golden spiral stores neighbours a ring apart; Z order stores most of them within a line.
TEST(SpatialOrder, NeighboursComeWithinACacheLine) {
  const PointModel spiral = make_sphere(40000);
  const PointModel ordered = reordered(spiral, spatial_order(spiral));
  const double before = neighbour_locality(spiral, PointIndex(spiral));
  const double after = neighbour_locality(ordered, PointIndex(ordered));
  std::printf("[ locality ] 40k golden spiral %.3f, Z order %.3f\n", before, after);
  EXPECT_LT(before, 0.35);
  EXPECT_GT(after, 0.5);
}

DeformSettings sphere_settings(double region_radius) {
  DeformSettings s = frames::sphere_settings(0.04, 0.05, region_radius);
  // The smallest patch a contact may have is a fraction of the median ball, which set-up
  // samples over the file's order (model_scale.hpp: a stride, so that it stays the same when
  // the model is scaled or turned); the two orders may see it one point apart. Off here.
  s.guards.min_patch_fraction = 0.0;
  return s;
}

// A stroke of three fingers, global and in a region, on the spiral and on its Z-ordered copy:
// the same points move to the same places. Nothing in a frame depends on the storage order but
// the order in which sums meet their terms, so the two agree to float rounding (here, to the bit).
TEST(SpatialOrder, AStrokeMovesTheSamePointsOnTheReorderedModel) {
  const PointModel spiral = make_sphere(20000);
  const std::vector<std::uint32_t> order = spatial_order(spiral);
  for (const double region : {0.0, 0.3}) {
    PointModel a = spiral;
    PointModel b = reordered(spiral, order);
    Deformer on_a(a, sphere_settings(region));
    Deformer on_b(b, sphere_settings(region));
    const Vec3 tops[3] = {normalized(Vec3{0.1, 0.0, 1.0}), normalized(Vec3{-0.3, 0.4, 1.0}),
                          normalized(Vec3{1.0, 0.2, 0.1})};
    std::size_t collisions = 0;
    for (int frame = 0; frame < 6; ++frame) {
      ProbeMotion probes[3];
      for (int f = 0; f < 3; ++f) {
        const Vec3 slide{0.01 * frame, 0.005 * frame, 0.0};
        probes[f] = {tops[f] * (1.0 - 0.01 * frame) + slide, tops[f] * (0.99 - 0.01 * frame) + slide, std::nullopt};
      }
      const std::size_t on_a_collisions = on_a.deform(probes).collisions;
      collisions += on_a_collisions;
      EXPECT_EQ(on_b.deform(probes).collisions, on_a_collisions) << "frame " << frame;
    }
    EXPECT_GT(collisions, 6u);
    double worst_position = 0.0, worst_normal = 0.0, largest_move = 0.0;
    for (std::size_t k = 0; k < b.size(); ++k) {
      const std::size_t i = order[k];
      worst_position = std::max(worst_position, norm(b.position(k) - a.position(i)));
      worst_normal = std::max(worst_normal, norm(b.normal(k) - a.normal(i)));
      largest_move = std::max(largest_move, norm(a.position(i) - spiral.position(i)));
    }
    std::printf("[ reordered ] region %.1f: largest move %.3g, positions apart %.3g, normals %.3g\n", region,
                largest_move, worst_position, worst_normal);
    EXPECT_GT(largest_move, 0.02);
    EXPECT_LE(worst_position, 1e-6 * largest_move);
    EXPECT_LE(worst_normal, 1e-5);
  }
}

}  // namespace
}  // namespace sculpt::deform
