// PLY reading and writing on valid files: round trips in every encoding, every numeric type,
// any property order, skipped extras, faces, and the file-level entry points.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"
#include "deform/ply_encoding_label.hpp"

namespace sculpt::deform {
namespace {

using ply_test::encoding_label;

constexpr PlyEncoding kAllEncodings[] = {PlyEncoding::kAscii, PlyEncoding::kBinaryLittleEndian,
                                         PlyEncoding::kBinaryBigEndian};

const char* format_line(PlyEncoding e) {
  switch (e) {
    case PlyEncoding::kAscii: return "format ascii 1.0\n";
    case PlyEncoding::kBinaryLittleEndian: return "format binary_little_endian 1.0\n";
    case PlyEncoding::kBinaryBigEndian: return "format binary_big_endian 1.0\n";
  }
  return "";
}

// Builds a PLY file by hand: header lines, then body values written in the file's encoding
// with the declared type, so tests can make any layout the spec allows.
class PlyBuilder {
 public:
  explicit PlyBuilder(PlyEncoding encoding) : encoding_(encoding) {}

  PlyBuilder& line(const std::string& header_line) {
    header_ += header_line + "\n";
    return *this;
  }

  /// One body value of PLY type `type` ("char" ... "double", or the sized names).
  PlyBuilder& value(const std::string& type, double v) {
    if (encoding_ == PlyEncoding::kAscii) {
      char text[64];
      if (type == "float" || type == "float32") {
        std::snprintf(text, sizeof text, "%.9g ", static_cast<double>(static_cast<float>(v)));
      } else if (type == "double" || type == "float64") {
        std::snprintf(text, sizeof text, "%.17g ", v);
      } else {
        std::snprintf(text, sizeof text, "%lld ", static_cast<long long>(v));
      }
      body_ += text;
      return *this;
    }
    if (type == "char" || type == "int8")
      put(static_cast<std::int8_t>(v));
    else if (type == "uchar" || type == "uint8")
      put(static_cast<std::uint8_t>(v));
    else if (type == "short" || type == "int16")
      put(static_cast<std::int16_t>(v));
    else if (type == "ushort" || type == "uint16")
      put(static_cast<std::uint16_t>(v));
    else if (type == "int" || type == "int32")
      put(static_cast<std::int32_t>(v));
    else if (type == "uint" || type == "uint32")
      put(static_cast<std::uint32_t>(v));
    else if (type == "float" || type == "float32")
      put(static_cast<float>(v));
    else if (type == "double" || type == "float64")
      put(v);
    else
      ADD_FAILURE() << "test builder: unknown type " << type;
    return *this;
  }

  /// Ends one element instance (a line in ascii; nothing in binary).
  PlyBuilder& end_row() {
    if (encoding_ == PlyEncoding::kAscii) body_ += "\n";
    return *this;
  }

  std::string build() const { return std::string("ply\n") + format_line(encoding_) + header_ + "end_header\n" + body_; }

 private:
  template <typename T>
  void put(T v) {
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    const bool want_big = encoding_ == PlyEncoding::kBinaryBigEndian;
    if (want_big != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    body_.append(raw, sizeof(T));
  }

  PlyEncoding encoding_;
  std::string header_;
  std::string body_;
};

// A model with awkward floats mixed in: signed zero, denormals, extremes and values with no
// short decimal form, so "bit-exact" really is tested. The extremes are the largest magnitudes
// a model may hold (just below kMaxCoordinate), since larger ones are refused.
PointModel awkward_model(std::size_t n, bool normals, bool colors, bool alpha, unsigned seed) {
  const float largest = std::nextafter(static_cast<float>(kMaxCoordinate), 0.0F);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-1000.0F, 1000.0F);
  std::uniform_int_distribution<int> byte(0, 255);
  const float specials[] = {0.0F,
                            -0.0F,
                            std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::min(),
                            largest,
                            -largest,
                            1.0F / 3.0F,
                            0.1F,
                            16777217.0F,
                            1e-30F,
                            9.99e17F};
  PointModel m;
  m.resize(n, normals, colors, alpha);
  for (std::size_t i = 0; i < n; ++i) {
    m.x[i] = i < std::size(specials) ? specials[i] : coord(rng);
    m.y[i] = coord(rng) * 1e-3F;
    m.z[i] = i + 1 < std::size(specials) ? specials[std::size(specials) - 1 - i] : coord(rng) * 1e5F;
    if (normals) {
      m.nx[i] = coord(rng) / 1000.0F;
      m.ny[i] = i == 0 ? -0.0F : coord(rng) / 1000.0F;
      m.nz[i] = coord(rng) / 1000.0F;
    }
    if (colors) {
      m.red[i] = static_cast<std::uint8_t>(byte(rng));
      m.green[i] = static_cast<std::uint8_t>(byte(rng));
      m.blue[i] = static_cast<std::uint8_t>(i % 2 == 0 ? 0 : 255);
    }
    if (alpha) m.alpha[i] = static_cast<std::uint8_t>(byte(rng));
  }
  return m;
}

// Compares float arrays bit for bit (so -0.0 != 0.0 and denormals must survive).
void expect_bits_equal(const std::vector<float>& expected, const std::vector<float>& actual, const char* what) {
  ASSERT_EQ(expected.size(), actual.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(expected[i]), std::bit_cast<std::uint32_t>(actual[i]))
        << what << "[" << i << "]: expected " << expected[i] << ", got " << actual[i];
  }
}

void expect_same_model(const PointModel& expected, const PointModel& actual) {
  expect_bits_equal(expected.x, actual.x, "x");
  expect_bits_equal(expected.y, actual.y, "y");
  expect_bits_equal(expected.z, actual.z, "z");
  expect_bits_equal(expected.nx, actual.nx, "nx");
  expect_bits_equal(expected.ny, actual.ny, "ny");
  expect_bits_equal(expected.nz, actual.nz, "nz");
  EXPECT_EQ(expected.red, actual.red);
  EXPECT_EQ(expected.green, actual.green);
  EXPECT_EQ(expected.blue, actual.blue);
  EXPECT_EQ(expected.alpha, actual.alpha);
  EXPECT_EQ(expected.triangles, actual.triangles);
}

// A per-test file name under the gtest temp dir (tests may run in parallel processes).
std::string temp_path(const std::string& file_name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string unique = std::string(info->test_suite_name()) + "_" + info->name() + "_" + file_name;
  std::replace(unique.begin(), unique.end(), '/', '_');
  return ::testing::TempDir() + unique;
}

// ---------------------------------------------------------------------------------------

class PlyRoundTrip : public ::testing::TestWithParam<PlyEncoding> {};

TEST_P(PlyRoundTrip, PositionsAreBitExact) {
  const PointModel model = awkward_model(200, false, false, false, 1);
  const PointModel back = read_ply_from_buffer(write_ply_to_buffer(model, GetParam()), "mem.ply");
  EXPECT_FALSE(back.has_normals());
  EXPECT_FALSE(back.has_colors());
  EXPECT_FALSE(back.has_alpha());
  expect_same_model(model, back);
}

TEST_P(PlyRoundTrip, NormalsAndColoursWithoutAlpha) {
  const PointModel model = awkward_model(150, true, true, false, 2);
  const PointModel back = read_ply_from_buffer(write_ply_to_buffer(model, GetParam()), "mem.ply");
  EXPECT_TRUE(back.has_normals());
  EXPECT_TRUE(back.has_colors());
  EXPECT_FALSE(back.has_alpha());
  expect_same_model(model, back);
}

TEST_P(PlyRoundTrip, ColoursWithAlpha) {
  const PointModel model = awkward_model(150, false, true, true, 3);
  const PointModel back = read_ply_from_buffer(write_ply_to_buffer(model, GetParam()), "mem.ply");
  EXPECT_TRUE(back.has_alpha());
  expect_same_model(model, back);
}

TEST_P(PlyRoundTrip, EmptyModel) {
  const PointModel back = read_ply_from_buffer(write_ply_to_buffer(PointModel{}, GetParam()), "e.ply");
  EXPECT_TRUE(back.empty());
  EXPECT_NO_THROW(back.validate());
}

TEST_P(PlyRoundTrip, ThroughAFile) {
  const PointModel model = awkward_model(64, true, true, true, 4);
  const std::string path = temp_path("model.ply");
  write_ply(path, model, GetParam());
  expect_same_model(model, read_ply(path));
  std::filesystem::remove(path);
}

TEST_P(PlyRoundTrip, FacesAreWrittenBack) {
  PointModel model = awkward_model(4, true, true, false, 5);
  model.triangles = {0, 1, 2, 0, 2, 3};
  const std::string bytes = write_ply_to_buffer(model, GetParam());
  EXPECT_NE(bytes.find("element face 2\nproperty list uchar int vertex_indices\nend_header\n"), std::string::npos);
  expect_same_model(model, read_ply_from_buffer(bytes, "m.ply"));
}

INSTANTIATE_TEST_SUITE_P(PlyAllEncodings, PlyRoundTrip, ::testing::ValuesIn(kAllEncodings),
                         [](const auto& info) { return encoding_label(info.param); });

TEST(PlyWriter, WritesTheStandardHeader) {
  PointModel model = awkward_model(3, true, true, true, 6);
  const std::string bytes = write_ply_to_buffer(model, PlyEncoding::kBinaryLittleEndian);
  const std::string expected_header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment generated by glovesculpt\n"
      "element vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property uchar alpha\n"
      "end_header\n";
  ASSERT_EQ(bytes.substr(0, expected_header.size()), expected_header);
  EXPECT_EQ(bytes.size(), expected_header.size() + 3 * (6 * 4 + 4));
}

TEST(PlyWriter, BigEndianBodyIsByteSwapped) {
  PointModel model;
  model.push_back({1.0, 0.0, 0.0});
  const std::string bytes = write_ply_to_buffer(model, PlyEncoding::kBinaryBigEndian);
  // 1.0f is 0x3F800000; big-endian puts 0x3F first.
  const std::string body = bytes.substr(bytes.size() - 12);
  EXPECT_EQ(static_cast<unsigned char>(body[0]), 0x3F);
  EXPECT_EQ(static_cast<unsigned char>(body[1]), 0x80);
  EXPECT_EQ(static_cast<unsigned char>(body[3]), 0x00);
}

TEST(PlyWriter, AsciiUsesShortestDigits) {
  PointModel model;
  model.push_back({0.1, -2.5, 1e-7});
  const std::string bytes = write_ply_to_buffer(model, PlyEncoding::kAscii);
  EXPECT_NE(bytes.find("end_header\n0.1 -2.5 1e-07\n"), std::string::npos) << bytes;
}

TEST(PlyWriter, RefusesInconsistentModels) {
  PointModel model = awkward_model(5, true, false, false, 7);
  model.ny.pop_back();
  EXPECT_THROW(write_ply_to_buffer(model), std::invalid_argument);
  model = awkward_model(5, true, false, false, 7);
  model.nz[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(write_ply_to_buffer(model), std::invalid_argument);
}

TEST(PlyWriter, UnwritablePathIsAModelFileError) {
  const std::string path = "/nonexistent-dir-for-glovesculpt/out.ply";
  try {
    write_ply(path, awkward_model(2, false, false, false, 8));
    FAIL() << "writing into a missing directory succeeded";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(std::string(e.what()).find(path + ": cannot create"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------
// Every PLY numeric type, under both of its names, for x, y and z, in every encoding.

struct TypeCase {
  const char* name;
  const char* alias;
  double x, y, z;  // values the type holds exactly
};

constexpr TypeCase kTypeCases[] = {
    {"char", "int8", -128, 127, -5},
    {"uchar", "uint8", 0, 255, 17},
    {"short", "int16", -32768, 32767, -300},
    {"ushort", "uint16", 0, 65535, 4000},
    {"int", "int32", -2147483648.0, 2147483647.0, -70000},
    {"uint", "uint32", 0, 4294967295.0, 123456789},
    {"float", "float32", -1.5, 3.25e-20, 1.0 / 3.0},
    {"double", "float64", 0.1, 123456.789, 2.5e-8},
};

// NOLINTNEXTLINE(readability-identifier-naming): gtest looks for this name
void PrintTo(const TypeCase& c, std::ostream* os) { *os << c.name << "/" << c.alias; }

class PlyNumericType : public ::testing::TestWithParam<std::tuple<PlyEncoding, TypeCase, bool /*alias*/>> {};

TEST_P(PlyNumericType, ReadsPositionsOfEveryType) {
  const auto& [encoding, type_case, use_alias] = GetParam();
  const std::string type = use_alias ? type_case.alias : type_case.name;
  PlyBuilder ply(encoding);
  ply.line("element vertex 2")
      .line("property " + type + " x")
      .line("property " + type + " y")
      .line("property " + type + " z");
  ply.value(type, type_case.x).value(type, type_case.y).value(type, type_case.z).end_row();
  ply.value(type, type_case.z).value(type, type_case.x).value(type, type_case.y).end_row();
  const PointModel m = read_ply_from_buffer(ply.build(), "types.ply");
  ASSERT_EQ(m.size(), 2u);
  // The reader converts to float exactly as a cast from the stored value would.
  const auto as_float = [](double v) { return static_cast<float>(v); };
  EXPECT_EQ(m.x[0], as_float(type_case.x));
  EXPECT_EQ(m.y[0], as_float(type_case.y));
  EXPECT_EQ(m.z[0], as_float(type_case.z));
  EXPECT_EQ(m.x[1], as_float(type_case.z));
  EXPECT_EQ(m.y[1], as_float(type_case.x));
  EXPECT_EQ(m.z[1], as_float(type_case.y));
}

INSTANTIATE_TEST_SUITE_P(PlyAllTypes, PlyNumericType,
                         ::testing::Combine(::testing::ValuesIn(kAllEncodings), ::testing::ValuesIn(kTypeCases),
                                            ::testing::Bool()),
                         [](const auto& info) {
                           return encoding_label(std::get<0>(info.param)) + "_" +
                                  (std::get<2>(info.param) ? std::get<1>(info.param).alias
                                                           : std::get<1>(info.param).name);
                         });

class PlyLayout : public ::testing::TestWithParam<PlyEncoding> {};

// Properties in an unusual order and with mixed types: big-endian doubles, uchar colours
// first, int16 positions, float colours.
TEST_P(PlyLayout, ShuffledPropertiesWithMixedTypes) {
  PlyBuilder ply(GetParam());
  ply.line("comment shuffled on purpose")
      .line("element vertex 3")
      .line("property uchar red")
      .line("property double z")
      .line("property float ny")
      .line("property uchar alpha")
      .line("property short y")
      .line("property double nz")
      .line("property uchar blue")
      .line("property int x")
      .line("property uint8 green")
      .line("property float nx");
  for (int i = 0; i < 3; ++i) {
    ply.value("uchar", 10 + i)
        .value("double", 0.125 * i)
        .value("float", 0.5)
        .value("uchar", 200 + i)
        .value("short", -1000 * i)
        .value("double", -0.5)
        .value("uchar", 30 + i)
        .value("int", 100000 + i)
        .value("uint8", 20 + i)
        .value("float", 0.25 * i)
        .end_row();
  }
  const PointModel m = read_ply_from_buffer(ply.build(), "shuffled.ply");
  ASSERT_EQ(m.size(), 3u);
  ASSERT_TRUE(m.has_normals());
  ASSERT_TRUE(m.has_colors());
  ASSERT_TRUE(m.has_alpha());
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(m.x[i], 100000.0F + static_cast<float>(i));
    EXPECT_EQ(m.y[i], -1000.0F * static_cast<float>(i));
    EXPECT_EQ(m.z[i], 0.125F * static_cast<float>(i));
    EXPECT_EQ(m.nx[i], 0.25F * static_cast<float>(i));
    EXPECT_EQ(m.ny[i], 0.5F);
    EXPECT_EQ(m.nz[i], -0.5F);
    EXPECT_EQ(m.red[i], 10 + i);
    EXPECT_EQ(m.green[i], 20 + i);
    EXPECT_EQ(m.blue[i], 30 + i);
    EXPECT_EQ(m.alpha[i], 200 + i);
  }
  EXPECT_NO_THROW(m.validate());
}

// Colour conversion: float/double are 0..1 scaled to 0..255; wider integers are clamped.
TEST_P(PlyLayout, ColourConversions) {
  PlyBuilder ply(GetParam());
  ply.line("element vertex 2")
      .line("property float x")
      .line("property float y")
      .line("property float z")
      .line("property float red")
      .line("property ushort green")
      .line("property char blue")
      .line("property double alpha");
  ply.value("float", 0).value("float", 0).value("float", 0);
  ply.value("float", 1.0).value("ushort", 1000).value("char", -5).value("double", 0.5).end_row();
  ply.value("float", 0).value("float", 0).value("float", 0);
  ply.value("float", 0.2).value("ushort", 77).value("char", 127).value("double", 1.5).end_row();
  const PointModel m = read_ply_from_buffer(ply.build(), "colours.ply");
  EXPECT_EQ(m.red, (std::vector<std::uint8_t>{255, 51}));
  EXPECT_EQ(m.green, (std::vector<std::uint8_t>{255, 77}));
  EXPECT_EQ(m.blue, (std::vector<std::uint8_t>{0, 127}));
  EXPECT_EQ(m.alpha, (std::vector<std::uint8_t>{128, 255}));
}

// Everything the model does not use must be skipped without upsetting what it does use:
// a vertex property "confidence", a list inside the vertex element, an "edge" element, face
// properties around the index list, and an element made only of lists.
TEST_P(PlyLayout, SkipsExtraPropertiesAndElements) {
  PlyBuilder ply(GetParam());
  ply.line("obj_info scanner glovesculpt-test")
      .line("element material 2")
      .line("property list uchar float coefficients")
      .line("property uchar id")
      .line("element vertex 5")
      .line("property float x")
      .line("property float confidence")
      .line("property list ushort int neighbours")
      .line("property float y")
      .line("property double z")
      .line("element face 4")
      .line("property uchar flags")
      .line("property list uchar uint vertex_indices")
      .line("property list int float texcoord")
      .line("element edge 2")
      .line("property int vertex1")
      .line("property int vertex2")
      .line("property uchar red");
  // material: a list then a scalar
  ply.value("uchar", 2).value("float", 0.5).value("float", 0.25).value("uchar", 1).end_row();
  ply.value("uchar", 0).value("uchar", 2).end_row();
  for (int i = 0; i < 5; ++i) {
    ply.value("float", i).value("float", 0.9);
    ply.value("ushort", i % 3);
    for (int k = 0; k < i % 3; ++k) ply.value("int", k);
    ply.value("float", 10 + i).value("double", 20 + i).end_row();
  }
  // faces: a triangle, a quad, a degenerate two-corner face and a pentagon
  const std::vector<std::vector<int>> faces = {{0, 1, 2}, {0, 1, 3, 4}, {2, 3}, {4, 3, 2, 1, 0}};
  for (const auto& face : faces) {
    ply.value("uchar", 7).value("uchar", static_cast<double>(face.size()));
    for (int v : face) ply.value("uint", v);
    ply.value("int", 2).value("float", 0.5).value("float", 0.75).end_row();
  }
  ply.value("int", 0).value("int", 1).value("uchar", 255).end_row();
  ply.value("int", 1).value("int", 2).value("uchar", 0).end_row();

  const PointModel m = read_ply_from_buffer(ply.build(), "extras.ply");
  ASSERT_EQ(m.size(), 5u);
  EXPECT_FALSE(m.has_normals());
  EXPECT_FALSE(m.has_colors());  // "red" belongs to the edge element, not to vertices
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(m.x[i], static_cast<float>(i));
    EXPECT_EQ(m.y[i], 10.0F + static_cast<float>(i));
    EXPECT_EQ(m.z[i], 20.0F + static_cast<float>(i));
  }
  const std::vector<std::uint32_t> expected_triangles = {0, 1, 2,           // triangle
                                                         0, 1, 3, 0, 3, 4,  // quad fanned into two
                                                         4, 3, 2, 4, 2, 1,
                                                         4, 1, 0};  // pentagon fanned into three; the 2-gon is dropped
  EXPECT_EQ(m.triangles, expected_triangles);
  EXPECT_NO_THROW(m.validate());
}

// Faces may come before vertices and use the "vertex_index" name and signed indices.
TEST_P(PlyLayout, FaceElementBeforeVerticesWithVertexIndexName) {
  PlyBuilder ply(GetParam());
  ply.line("element face 1")
      .line("property list int short vertex_index")
      .line("element vertex 4")
      .line("property float x")
      .line("property float y")
      .line("property float z");
  ply.value("int", 4).value("short", 3).value("short", 2).value("short", 1).value("short", 0).end_row();
  for (int i = 0; i < 4; ++i) ply.value("float", i).value("float", 0).value("float", 0).end_row();
  const PointModel m = read_ply_from_buffer(ply.build(), "order.ply");
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m.triangles, (std::vector<std::uint32_t>{3, 2, 1, 3, 1, 0}));
}

TEST_P(PlyLayout, ZeroVerticesIsAnEmptyModel) {
  PlyBuilder ply(GetParam());
  ply.line("element vertex 0").line("property float x").line("property float y").line("property float z");
  ply.line("element face 0").line("property list uchar int vertex_indices");
  const PointModel m = read_ply_from_buffer(ply.build(), "empty.ply");
  EXPECT_TRUE(m.empty());
  EXPECT_TRUE(m.triangles.empty());
}

INSTANTIATE_TEST_SUITE_P(PlyAllEncodings, PlyLayout, ::testing::ValuesIn(kAllEncodings),
                         [](const auto& info) { return encoding_label(info.param); });

// ---------------------------------------------------------------------------------------
// Header and text details.

TEST(PlyHeaderText, CrLfLineEndingsInAsciiFiles) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\ncomment made on windows\r\nelement vertex 2\r\n"
      "property float x\r\nproperty float y\r\nproperty float z\r\nend_header\r\n"
      "1 2 3\r\n4 5 6\r\n";
  const PointModel m = read_ply_from_buffer(text, "crlf.ply");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.position(1), (Vec3{4, 5, 6}));
}

TEST(PlyHeaderText, CrLfHeaderBeforeABinaryBody) {
  // The body starts right after "end_header\r\n"; the first body byte is 0x0A on purpose,
  // so a reader that strips whitespace after the header would be caught.
  std::string text =
      "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 1\r\n"
      "property uchar x\r\nproperty uchar y\r\nproperty uchar z\r\nend_header\r\n";
  text += std::string("\x0a\x0d\x20", 3);
  const PointModel m = read_ply_from_buffer(text, "crlf_bin.ply");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m.position(0), (Vec3{10, 13, 32}));
}

TEST(PlyHeaderText, AsciiToleratesTrailingSpacesTabsAndBlankLines) {
  // The Stanford dragon files end every body line with a space.
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0.5 1e-3 -2 \n\t+1.25\t0 0\n\n3 0 1 1 \n\n";
  const PointModel m = read_ply_from_buffer(text, "spaces.ply");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.y[0], 1e-3F);
  EXPECT_EQ(m.x[1], 1.25F);
  EXPECT_EQ(m.triangles, (std::vector<std::uint32_t>{0, 1, 1}));
}

TEST(PlyHeaderText, TrailingBytesAfterTheBodyAreIgnored) {
  PointModel model = awkward_model(3, false, false, false, 9);
  const std::string bytes = write_ply_to_buffer(model) + "\n\n";
  expect_same_model(model, read_ply_from_buffer(bytes, "trailing.ply"));
}

TEST(PlyHeaderText, AsciiReadsOutOfRangeNumbersAsInfinityOrZero) {
  // 1e-50 underflows a float to 0 and is fine; 1e39 overflows it to infinity and is an error.
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property double z\nend_header\n";
  const PointModel m = read_ply_from_buffer(header + "1e-50 -1e-50 1e-400\n", "tiny.ply");
  EXPECT_EQ(m.x[0], 0.0F);
  EXPECT_TRUE(std::signbit(m.y[0]));
  EXPECT_EQ(m.z[0], 0.0F);
  EXPECT_THROW(read_ply_from_buffer(header + "1e39 0 0\n", "huge.ply"), ModelFileError);
  EXPECT_THROW(read_ply_from_buffer(header + "0 0 1e400\n", "huge.ply"), ModelFileError);
}

// ---------------------------------------------------------------------------------------
// File-level entry points.

TEST(ModelIo, DispatchesOnTheExtensionCaseInsensitively) {
  const PointModel model = awkward_model(20, true, true, false, 10);
  const std::string ply = temp_path("Model.PLY");
  write_model(ply, model, PlyEncoding::kAscii);
  expect_same_model(model, read_model(ply));

  const std::string xyz = temp_path("model.Xyz");
  write_model(xyz, model);
  const PointModel back = read_model(xyz);
  expect_bits_equal(model.x, back.x, "x");
  expect_bits_equal(model.nz, back.nz, "nz");
  EXPECT_FALSE(back.has_colors());  // xyz has no colours
  std::filesystem::remove(ply);
  std::filesystem::remove(xyz);
}

TEST(ModelIo, UnknownExtensionsAreRefusedWithTheirName) {
  try {
    read_model("scan.obj");
    FAIL() << "read_model accepted .obj";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(std::string(e.what()), "scan.obj: cannot read models with extension '.obj' (use .ply, .off or .xyz)");
    EXPECT_TRUE(e.where().empty());
  }
  EXPECT_THROW(read_model("no_extension"), ModelFileError);
  EXPECT_THROW(write_model(temp_path("out.obj"), awkward_model(2, false, false, false, 11)), ModelFileError);
}

TEST(ModelIo, MissingFilesAndDirectoriesAreModelFileErrors) {
  const std::string missing = temp_path("does_not_exist.ply");
  try {
    read_ply(missing);
    FAIL() << "read a missing file";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(e.path(), missing);
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_model(::testing::TempDir() + "."), ModelFileError);
  const std::string dir = temp_path("dir.ply");
  std::filesystem::create_directories(dir);
  EXPECT_THROW(read_ply(dir), ModelFileError);
  std::filesystem::remove(dir);
}

TEST(ModelIo, ErrorsFromFilesNameTheFullPath) {
  const std::string path = temp_path("bad.ply");
  {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n1 2 oops\n";
  }
  try {
    read_model(path);
    FAIL() << "read a malformed file";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_EQ(e.where(), "line 8");
    EXPECT_EQ(std::string(e.what()).rfind(path + ": line 8: 'oops' is not a number", 0), 0u) << e.what();
  }
  std::filesystem::remove(path);
}

// A real scan, when the fetch script has put it in place: the decimated Stanford dragon.
TEST(PlyRealScan, StanfordDragon100k) {
  const std::string path = SCULPT_SOURCE_DIR "/data/scans/dragon_100250.ply";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << path << " is absent (run the scan fetch script to get it)";
  }
  const PointModel m = read_model(path);
  EXPECT_EQ(m.size(), 100250u);
  EXPECT_EQ(m.triangles.size(), 3u * 202520u);
  EXPECT_NO_THROW(m.validate());
  EXPECT_GT(m.bounding_box_diagonal(), 0.1);
}

}  // namespace
}  // namespace sculpt::deform
