// Settings and probe positions checked against the model: finite, of the right sign, and within
// 1e3 bounding-box diagonals; every refusal names the setting as the caller calls it.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sculpt/deform/settings_range.hpp"

namespace sculpt::deform {
namespace {

// A box from (0, 0, 0) to (3, 4, 12): centre (1.5, 2, 6), diagonal 13.
PointModel box() {
  PointModel m;
  m.push_back({0, 0, 0});
  m.push_back({3, 4, 12});
  m.push_back({1, 1, 1});
  return m;
}

DeformSettings sensible() {
  DeformSettings s;
  s.contact.bc_radius = 0.1;
  s.contact.min_source_distance = 0.025;
  s.contact.guard_distance = 0.15;
  return s;
}

std::string refusal(const DeformSettings& s, const SettingNames& names = {}) {
  try {
    check_settings_against_model(s, box(), names);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ModelExtent, IsTheBoundingBoxCentreAndDiagonal) {
  const ModelExtent e = ModelExtent::of(box());
  EXPECT_EQ(e.centre, (Vec3{1.5, 2, 6}));
  EXPECT_DOUBLE_EQ(e.diagonal, 13.0);
}

TEST(SettingsRange, SensibleSettingsPass) {
  EXPECT_EQ(refusal(sensible()), "accepted");
  DeformSettings s = sensible();
  s.contact.guard_distance = 0.0;  // 0: no guard
  s.region.border_width = 0.0;     // 0: the bc radius
  s.contact.bc_radius = 13e3;      // exactly 1e3 diagonals
  EXPECT_EQ(refusal(s), "accepted");
}

TEST(SettingsRange, ALengthBeyondAThousandDiagonalsIsRefusedByName) {
  SettingNames names;
  names.min_source_distance = "deform.delta_d";
  DeformSettings s = sensible();
  s.contact.min_source_distance = 1e30;
  EXPECT_EQ(refusal(s, names),
            "deform.delta_d = 1e+30 is too large, more than 1000 bounding-box diagonals of the model "
            "(its diagonal is 13)");
}

TEST(SettingsRange, NonFiniteAndWrongSignAreRefusedByName) {
  SettingNames names;
  names.bc_radius = "--bc-radius";
  names.guard_distance = "--delta-r";
  DeformSettings s = sensible();
  s.contact.bc_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(s, names).find("--bc-radius = nan must be a finite number"), std::string::npos);
  s = sensible();
  s.contact.bc_radius = 0.0;
  EXPECT_NE(refusal(s, names).find("--bc-radius = 0 must be > 0"), std::string::npos);
  s = sensible();
  s.contact.guard_distance = -1e-9;  // printed as 1e-09, not as 0.000000
  EXPECT_NE(refusal(s, names).find("--delta-r = -1e-09 must be >= 0"), std::string::npos) << refusal(s, names);
}

TEST(SettingsRange, RegionAndKernelLengthsAreCheckedWhenUsed) {
  DeformSettings s = sensible();
  s.region.radius = 1e9;  // a global region has no radius to check
  EXPECT_EQ(refusal(s), "accepted");
  s.region.kind = RegionSettings::Kind::kRadius;
  EXPECT_NE(refusal(s).find("region radius = 1e+09 is too large"), std::string::npos);
  s = sensible();
  s.region.border_width = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal(s).find("region border width = inf must be a finite number"), std::string::npos);
  s = sensible();
  s.kernel.kind = KernelKind::kRegularized;
  s.kernel.regularization = 2e5;
  EXPECT_NE(refusal(s).find("kernel regularization = 200000 is too large"), std::string::npos);
}

TEST(PositionRange, ProbesFarFromTheModelAreRefusedByName) {
  const ModelExtent e = ModelExtent::of(box());
  EXPECT_NO_THROW(check_position_against_model("--contact 0", {1.5 + 13e3, 2, 6}, e));
  try {
    check_position_against_model("--contact 1", {1e20, 0, 0}, e);
    ADD_FAILURE() << "accepted a probe at 1e20";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "--contact 1: (1e+20, 0, 0) is 1e+20 from the model's centre, more than 1000 bounding-box "
              "diagonals of the model (its diagonal is 13)");
  }
  // Beyond the range of a squared double: the distance is still said as a number, not inf.
  try {
    check_position_against_model("--contact 2", {1e300, 0, 0}, e);
    ADD_FAILURE() << "accepted a probe at 1e300";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("is 1e+300 from the model's centre"), std::string::npos) << error.what();
  }
  EXPECT_THROW(check_position_against_model("p", {0, std::nan(""), 0}, e), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
