#include "sculpt/deform/point_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sculpt::deform {
namespace {

TEST(PointModel, ResizeKeepsOptionalAttributesInStep) {
  PointModel m;
  m.resize(4, /*with_normals=*/true, /*with_colors=*/false);
  EXPECT_EQ(m.size(), 4u);
  EXPECT_TRUE(m.has_normals());
  EXPECT_FALSE(m.has_colors());
  m.push_back({1.0, 2.0, 3.0});
  EXPECT_EQ(m.nx.size(), 5u);
  EXPECT_EQ(m.position(4), (Vec3{1.0, 2.0, 3.0}));
  EXPECT_NO_THROW(m.validate());
}

TEST(PointModel, ValidateNamesTheBadAttribute) {
  PointModel m;
  m.resize(3, true, false);
  m.ny.pop_back();
  try {
    m.validate();
    FAIL() << "validate accepted mismatched normals";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'ny'"), std::string::npos) << e.what();
  }
}

TEST(PointModel, ValidateRejectsNonFiniteAndBadTriangles) {
  PointModel m;
  m.resize(3, false, false);
  m.triangles = {0, 1, 3};
  EXPECT_THROW(m.validate(), std::invalid_argument);
  m.triangles = {0, 1, 2};
  EXPECT_NO_THROW(m.validate());
  m.y[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(m.validate(), std::invalid_argument);
}

TEST(PointModel, BoundingBoxDiagonalOfUnitCube) {
  PointModel m;
  m.push_back({0, 0, 0});
  m.push_back({1, 1, 1});
  EXPECT_DOUBLE_EQ(m.bounding_box_diagonal(), std::sqrt(3.0));
}

TEST(PointModel, BoundingBoxTakesEachAxisFromItsOwnExtremePoint) {
  PointModel m;
  EXPECT_EQ(m.bounding_box().lo, Vec3{});
  EXPECT_EQ(m.bounding_box().hi, Vec3{});
  EXPECT_EQ(m.bounding_box_centre(), Vec3{});
  m.push_back({3, -1, 0.5});
  m.push_back({-2, 4, 0.25});
  m.push_back({1, 0, -6});
  const PointModel::Box box = m.bounding_box();
  EXPECT_EQ(box.lo, (Vec3{-2, -1, -6}));
  EXPECT_EQ(box.hi, (Vec3{3, 4, 0.5}));
  EXPECT_EQ(m.bounding_box_centre(), (Vec3{0.5, 1.5, -2.75}));
  EXPECT_DOUBLE_EQ(m.bounding_box_diagonal(), std::sqrt(25.0 + 25.0 + 6.5 * 6.5));
}

}  // namespace
}  // namespace sculpt::deform
