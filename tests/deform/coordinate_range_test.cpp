// Coordinates a model may hold (kMaxCoordinate): every reader refuses a vertex beyond the range
// naming the file and the vertex, and PointModel::validate() holds models built in code to the
// same rule.

#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

// Reads `bytes` with `read` and returns the error message, or "accepted".
template <typename Read>
std::string outcome(Read read, const std::string& bytes, const std::string& name) {
  try {
    read(bytes, name);
  } catch (const ModelFileError& e) {
    return e.what();
  }
  return "accepted";
}

void expect_refused(const std::string& message, const std::string& where) {
  SCOPED_TRACE(message);
  EXPECT_EQ(message.rfind(where, 0), 0u) << "should start with " << where;
  EXPECT_NE(message.find("out of range"), std::string::npos);
  EXPECT_NE(message.find("below 1e+18"), std::string::npos);
}

std::string ascii_ply(const std::string& second_vertex) {
  return "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n0 0 0\n" +
         second_vertex + "\n";
}

const std::string kBinaryHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n";

std::string little_endian(float v) {
  auto bits = std::bit_cast<std::uint32_t>(v);
  std::string bytes;
  for (int b = 0; b < 4; ++b, bits >>= 8) bytes += static_cast<char>(bits & 0xFF);
  return bytes;
}

std::string binary_ply(float x, float y, float z) {
  std::string bytes = kBinaryHeader;
  for (const float v : {0.0F, 0.0F, 0.0F, x, y, z}) bytes += little_endian(v);
  return bytes;
}

const std::string kFltMax = "3.4028235e38";  // FLT_MAX, finite in float

TEST(CoordinateRange, PlyAsciiRefusesAVertexAtFltMax) {
  const std::string message = outcome(read_ply_from_buffer, ascii_ply("0 " + kFltMax + " 0"), "bad.ply");
  expect_refused(message, "bad.ply: line 9: 'y' = 3.40282e+38 in vertex 1");
}

TEST(CoordinateRange, PlyBinaryRefusesAVertexAtFltMax) {
  const std::string message = outcome(read_ply_from_buffer, binary_ply(0.0F, 0.0F, FLT_MAX), "bad.ply");
  // The offset is that of the vertex: the header, then one vertex of three floats.
  expect_refused(
      message, "bad.ply: byte offset " + std::to_string(kBinaryHeader.size() + 12) + ": 'z' = 3.40282e+38 in vertex 1");
}

TEST(CoordinateRange, OffRefusesAVertexAtFltMax) {
  const std::string message = outcome(read_off_from_buffer, "OFF\n2 0 0\n0 0 0\n" + kFltMax + " 0 0\n", "bad.off");
  expect_refused(message, "bad.off: line 4: 'x' = 3.40282e+38 in vertex 1");
}

TEST(CoordinateRange, XyzRefusesAPointAtFltMax) {
  const std::string message = outcome(read_xyz_from_buffer, "0 0 0\n0 0 -" + kFltMax + "\n", "bad.xyz");
  expect_refused(message, "bad.xyz: line 2: 'z' = -3.40282e+38 in point 1");
}

TEST(CoordinateRange, EveryReaderAcceptsAVertexAt1e17) {
  EXPECT_EQ(read_ply_from_buffer(ascii_ply("1e17 0 -1e17"), "ok.ply").x[1], 1e17F);
  EXPECT_EQ(read_ply_from_buffer(binary_ply(0.0F, 1e17F, 0.0F), "ok.ply").y[1], 1e17F);
  EXPECT_EQ(read_off_from_buffer("OFF\n2 0 0\n0 0 0\n0 0 1e17\n", "ok.off").z[1], 1e17F);
  EXPECT_EQ(read_xyz_from_buffer("0 0 0\n-1e17 0 0\n", "ok.xyz").x[1], -1e17F);
}

TEST(CoordinateRange, ValidateRefusesWhatTheReadersRefuse) {
  PointModel m;
  m.push_back({0, 0, 0});
  m.push_back({0, 1e17, 0});
  EXPECT_NO_THROW(m.validate());
  for (const float bad :
       {FLT_MAX, -2e18F, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    PointModel copy = m;
    copy.y[1] = bad;
    try {
      copy.validate();
      ADD_FAILURE() << "accepted y = " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'y' = "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("in point 1 is out of range"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace sculpt::deform
