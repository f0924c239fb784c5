// Malformed PLY files: each must throw ModelFileError whose message names the file, the
// line or byte offset, and the problem, exactly as a user would need to fix it.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

// Little-endian bytes of a value, whatever the host.
template <typename T>
std::string le(T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (std::endian::native == std::endian::big) std::reverse(raw, raw + sizeof(T));
  return std::string(raw, sizeof(T));
}

std::string le_point(float x, float y, float z) { return le(x) + le(y) + le(z); }

// 7 header lines, so the ascii body starts on line 8.
std::string ascii_xyz(int vertices) {
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

std::string binary_xyz(int vertices) {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

std::string offset(const std::string& header, std::size_t body_bytes) {
  return "byte offset " + std::to_string(header.size() + body_bytes);
}

struct MalformedCase {
  std::string label;
  std::string bytes;
  std::vector<std::string> expected;  // substrings of what(), in addition to the file name
};

// NOLINTNEXTLINE(readability-identifier-naming): gtest looks for this name
void PrintTo(const MalformedCase& c, std::ostream* os) { *os << c.label; }

std::vector<MalformedCase> malformed_cases() {
  std::vector<MalformedCase> cases;
  auto add = [&cases](std::string label, std::string bytes, std::vector<std::string> expected) {
    cases.push_back({std::move(label), std::move(bytes), std::move(expected)});
  };
  const float inf = std::numeric_limits<float>::infinity();

  // --- header ---
  add("EmptyFile", "", {"bad.ply: line 1: missing magic 'ply'"});
  add("WrongMagic", "PLY\nformat ascii 1.0\n", {"bad.ply: line 1: missing magic 'ply'"});
  add("MagicNotAlone", "ply format ascii 1.0\nend_header\n", {"bad.ply: line 1: missing magic 'ply'"});
  add("UnknownFormat", "ply\nformat binary_middle_endian 1.0\nend_header\n",
      {"bad.ply: line 2: unknown format 'binary_middle_endian'"});
  add("UnsupportedVersion", "ply\nformat ascii 2.0\nend_header\n", {"bad.ply: line 2: unsupported version '2.0'"});
  add("MissingFormat",
      "ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 "
      "0 0\n",
      {"bad.ply: line 6: no format line before end_header"});
  add("ElementCountNotANumber", "ply\nformat ascii 1.0\nelement vertex lots\n",
      {"bad.ply: line 3: bad element count 'lots' for element 'vertex'"});
  add("ElementCountNegative", "ply\nformat ascii 1.0\nelement vertex -3\n",
      {"bad.ply: line 3: bad element count '-3'"});
  add("ElementCountOverflows", "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n",
      {"bad.ply: line 3: bad element count '99999999999999999999999'"});
  add("UnknownPropertyType",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float128 z\nend_header\n",
      {"bad.ply: line 6: unknown property type 'float128'"});
  add("UnknownListItemType", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar long vertex_indices\n",
      {"bad.ply: line 4: unknown property type 'long'"});
  add("FloatListCount", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\n",
      {"bad.ply: line 4: list count type 'float' is not an integer type"});
  add("PropertyBeforeElement", "ply\nformat ascii 1.0\nproperty float x\n",
      {"bad.ply: line 3: property before any element"});
  add("UnknownKeyword", "ply\nformat ascii 1.0\nelemnt vertex 3\n",
      {"bad.ply: line 3: unknown header keyword 'elemnt'"});
  add("DuplicateProperty",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property double y\n",
      {"bad.ply: line 6: property 'y' declared twice in element 'vertex'"});
  add("DuplicateVertexElement", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement vertex 2\n",
      {"bad.ply: line 5: element 'vertex' declared twice"});
  add("TextAfterEndHeader", "ply\nformat ascii 1.0\nend_header now\n",
      {"bad.ply: line 3: unexpected text after end_header"});
  add("HeaderTruncatedNoEndHeader",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\n",
      {"bad.ply: line 7: header truncated"});
  add("HeaderTruncatedMidLine", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nprop",
      {"bad.ply: line 4: header truncated"});
  add("OnlyMagic", "ply", {"bad.ply: line 2: header truncated"});

  // --- vertex layout ---
  add("MissingZ",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 "
      "2\n",
      {"bad.ply: line 3: element 'vertex' has no property 'z'"});
  add("MissingX",
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float y\n"
      "property float z\nend_header\n" +
          std::string(8, '\0'),
      {"bad.ply: line 3: element 'vertex' has no property 'x'"});
  add("PartialNormals",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nproperty float ny\nend_header\n0 0 0 1 0\n",
      {"bad.ply: line 3: element 'vertex' has no property 'nz'"});
  add("PositionIsAList",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\n"
      "property float z\nend_header\n1 0 0 0\n",
      {"bad.ply: line 3: vertex property 'x' is a list"});
  add("NoVertexElement", "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
      {"bad.ply: line 5: no 'vertex' element"});
  add("FloatFaceIndices",
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n"
      "3 0 1 2\n",
      {"bad.ply: line 7: face list 'vertex_indices' has non-integer item type 'float'"});
  add("MoreVerticesThanIndicesCanHold",
      "ply\nformat ascii 1.0\nelement vertex 5000000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n",
      {"bad.ply: line 3: too many vertices: 5000000000"});

  // --- counts the file cannot hold (must fail before allocating) ---
  {
    const std::string header = binary_xyz(400000000);
    add("BinaryCountLargerThanFile", header + le_point(1, 2, 3) + le_point(4, 5, 6),
        {"bad.ply: " + offset(header, 24) + ": body truncated: expected 400000000 vertices, read 2"});
  }
  add("AsciiCountLargerThanFile", ascii_xyz(2000000) + "1 2 3\n4 5 6\n",
      {"bad.ply: line 8: body truncated: expected 2000000 vertices, but the 12 bytes left can "
       "hold at most 2"});
  add("AsciiFaceCountLargerThanFile",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 100000\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n3 0 0 0\n",
      {"bad.ply: line 11: body truncated: expected 100000 faces, but the 8 bytes left can hold at "
       "most 4"});

  // --- ascii body ---
  add("HeaderLineAfterEndHeader", ascii_xyz(1) + "property float w\n1 2 3\n",
      {"bad.ply: line 8: header line 'property' after end_header"});
  add("AsciiNotANumber", ascii_xyz(1) + "1 2 abc\n",
      {"bad.ply: line 8: 'abc' is not a number (property 'z' of vertex 0)"});
  add("AsciiNumberWithJunk", ascii_xyz(1) + "1 2.5x 3\n",
      {"bad.ply: line 8: '2.5x' is not a number (property 'y' of vertex 0)"});
  add("AsciiTooFewValues", ascii_xyz(2) + "1.0 2.0 3.0\n4.0 5.0\n",
      {"bad.ply: line 9: too few values for vertex 1", "before 'z'"});
  add("AsciiTooManyValues", ascii_xyz(1) + "1 2 3 4\n", {"bad.ply: line 8: too many values for vertex 0"});
  add("AsciiBodyTruncated", ascii_xyz(3) + "1.000000 2.000000 3.000000\n4.000000 5.000000 6.000000\n",
      {"bad.ply: line 10: body truncated: expected 3 vertices, read 2"});
  add("AsciiNaN", ascii_xyz(2) + "0 0 0\nnan 0 0\n", {"bad.ply: line 9: non-finite 'x' in vertex 1"});
  add("AsciiInfinityOverflow", ascii_xyz(1) + "0 -1e39 0\n", {"bad.ply: line 8: non-finite 'y' in vertex 0"});
  add("AsciiFaceIndexOutOfRange",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n",
      {"bad.ply: line 14: face 1 refers to vertex 3, but there are only 3 vertices"});
  add("AsciiNegativeListLength",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n-1 0\n",
      {"bad.ply: line 11: negative length -1 for list 'vertex_indices'"});
  add("AsciiListShorterThanItsLength",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",
      {"bad.ply: line 13: too few values for face 0"});
  add("CrLfLineNumbers",
      "ply\r\nformat ascii 1.0\r\nelement vertex 1\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nend_header\r\n1 2 x3\r\n",
      {"bad.ply: line 8: 'x3' is not a number"});

  // --- binary body ---
  {
    const std::string header = binary_xyz(3);
    add("BinaryBodyTruncated", header + le_point(1, 2, 3) + le_point(4, 5, 6) + le(7.0F),
        {"bad.ply: " + offset(header, 24) + ": body truncated: expected 3 vertices, read 2"});
    add("BinaryEmptyBody", header, {"bad.ply: " + offset(header, 0) + ": body truncated: expected 3 vertices, read 0"});
    add("BinaryInfinity", header + le_point(1, 2, 3) + le_point(4, 5, 6) + le_point(7, inf, 9),
        {"bad.ply: " + offset(header, 24) + ": non-finite 'y' in vertex 2"});
  }
  {
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
        "property double y\nproperty double z\nproperty float nx\nproperty float ny\n"
        "property float nz\nend_header\n";
    add("BinaryDoubleOverflowsFloat", header + le(0.0) + le(0.0) + le(1e300) + le(0.0F) + le(0.0F) + le(1.0F),
        {"bad.ply: " + offset(header, 0) + ": non-finite 'z' in vertex 0"});
  }
  {
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n";
    const std::string vertices = le_point(0, 0, 0) + le_point(1, 0, 0) + le_point(0, 1, 0);
    const std::string face0 = le<std::uint8_t>(3) + le(0) + le(1) + le(2);
    add("BinaryFaceIndexNegative", header + vertices + face0 + le<std::uint8_t>(3) + le(0) + le(-1) + le(2),
        {"bad.ply: " + offset(header, 36 + 13) + ": face 1 refers to vertex -1, but there are only 3 vertices"});
    add("BinaryFacesTruncated", header + vertices + face0 + le<std::uint8_t>(3) + le(0) + le(1),
        {"bad.ply: " + offset(header, 36 + 13) + ": body truncated: expected 2 faces, read 1"});
  }
  {
    const std::string header =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list uint uchar vertex_indices\nend_header\n";
    // A list claiming four billion items in a file of a few bytes: refused without looping.
    add("BinaryHugeListLength", header + le_point(0, 0, 0) + le<std::uint32_t>(0xFFFFFFFFU) + "\1\2",
        {"bad.ply: " + offset(header, 12) + ": body truncated: expected 1 face, read 0"});
  }
  {
    const std::string header =
        "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list char uchar vertex_indices\nend_header\n";
    add("BinaryNegativeListLength", header + std::string(12, '\0') + "\xff",
        {"bad.ply: " + offset(header, 12) + ": negative length -1 for list 'vertex_indices'"});
  }
  // A binary body read as ascii: the message must stay short and printable.
  add("BinaryGarbageInAsciiBody", ascii_xyz(1) + std::string(5000, '\x01') + "\n",
      {"bad.ply: line 8: '?????", "...' is not a number"});
  return cases;
}

class PlyMalformedFile : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(PlyMalformedFile, ThrowsModelFileErrorNamingFileWhereAndProblem) {
  const MalformedCase& c = GetParam();
  try {
    const PointModel m = read_ply_from_buffer(c.bytes, "bad.ply");
    FAIL() << "accepted a malformed file; read " << m.size() << " points";
  } catch (const ModelFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.path(), "bad.ply");
    EXPECT_EQ(what.rfind("bad.ply: " + e.where() + ": ", 0), 0u) << what;
    EXPECT_LT(what.size(), 300u) << what;
    for (const std::string& expected : c.expected) {
      EXPECT_NE(what.find(expected), std::string::npos) << "message: " << what << "\nexpected to contain: " << expected;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PlyMalformed, PlyMalformedFile, ::testing::ValuesIn(malformed_cases()),
                         [](const auto& info) { return info.param.label; });

TEST(PlyMalformedTable, CoversEnoughCases) { EXPECT_GE(malformed_cases().size(), 15u); }

TEST(PlyMalformedError, WhatIsPathWhereProblem) {
  const ModelFileError e("scan.ply", "line 3", "bad element count 'x'");
  EXPECT_EQ(std::string(e.what()), "scan.ply: line 3: bad element count 'x'");
  EXPECT_EQ(e.path(), "scan.ply");
  EXPECT_EQ(e.where(), "line 3");
  EXPECT_EQ(e.problem(), "bad element count 'x'");
  const ModelFileError whole_file("scan.ply", "", "cannot open");
  EXPECT_EQ(std::string(whole_file.what()), "scan.ply: cannot open");
}

}  // namespace
}  // namespace sculpt::deform
