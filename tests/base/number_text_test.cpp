// number_text: the %g every message prints numbers with, where std::to_string's %f printed
// 1e-9 as 0.000000 and the largest double as 309 digits.

#include "sculpt/base/number_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace sculpt::base {
namespace {

TEST(NumberText, PrintsShortestGeneralForm) {
  EXPECT_EQ(number_text(0.5), "0.5");
  EXPECT_EQ(number_text(1e-9), "1e-09");
  EXPECT_EQ(number_text(3e7), "3e+07");
  EXPECT_EQ(number_text(1000.0), "1000");
  EXPECT_EQ(number_text(std::numeric_limits<double>::max()), "1.79769e+308");
  EXPECT_EQ(number_text(-std::numeric_limits<double>::max()), "-1.79769e+308");
  EXPECT_EQ(number_text(std::nan("")), "nan");
  EXPECT_EQ(number_text(std::numeric_limits<double>::infinity()), "inf");
}

}  // namespace
}  // namespace sculpt::base
