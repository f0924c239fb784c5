// OFF and XYZ reading (and XYZ writing): small hand-written files, their malformed cousins,
// a little fuzzing, and the real scans when the fetch script has put them in place.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

// Expects read to throw ModelFileError whose what() contains `expected`.
template <typename Read>
void expect_error(Read read, const std::string& name, const std::string& text, const std::string& expected) {
  try {
    const PointModel m = read(text, name);
    ADD_FAILURE() << "accepted:\n" << text << "\n(read " << m.size() << " points)";
  } catch (const ModelFileError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << expected;
  }
}

void expect_off_error(const std::string& text, const std::string& expected) {
  expect_error(read_off_from_buffer, "bad.off", text, expected);
}

void expect_xyz_error(const std::string& text, const std::string& expected) {
  expect_error(read_xyz_from_buffer, "bad.xyz", text, expected);
}

// ------------------------------------------------------------------------------------------
// OFF

TEST(OffReader, CubeWithCommentsAndQuads) {
  const std::string text =
      "# a unit cube\n"
      "OFF\n"
      "\n"
      "8 6 12  # vertices faces edges\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
      "# top\n"
      "0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const PointModel m = read_off_from_buffer(text, "cube.off");
  ASSERT_EQ(m.size(), 8u);
  EXPECT_EQ(m.position(6), (Vec3{1, 1, 1}));
  ASSERT_EQ(m.triangles.size(), 6u * 2 * 3);
  EXPECT_EQ((std::vector<std::uint32_t>(m.triangles.begin(), m.triangles.begin() + 6)),
            (std::vector<std::uint32_t>{0, 3, 2, 0, 2, 1}));
  EXPECT_FALSE(m.has_normals());
  EXPECT_FALSE(m.has_colors());
  EXPECT_NO_THROW(m.validate());
}

TEST(OffReader, CountsOnTheKeywordLineAndPolygonsFanned) {
  const std::string text =
      "OFF 6 3 0\n"
      "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 2 0\n-1 1 0\n"
      "6 0 1 2 3 4 5 255 0 0\n"  // a hexagon with a face colour after the indices
      "2 0 1\n"                  // degenerate: dropped
      "3 5 4 3\n";
  const PointModel m = read_off_from_buffer(text, "hex.off");
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m.triangles, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 5, 4, 3}));
}

TEST(OffReader, NormalsColoursCrLfAndExtraValues) {
  const std::string noff = "NOFF\r\n2 0 0\r\n0 0 0 0 0 1\r\n1 2 3 0 1 0 \r\n";
  const PointModel n = read_off_from_buffer(noff, "n.off");
  ASSERT_TRUE(n.has_normals());
  EXPECT_EQ(n.normal(1), (Vec3{0, 1, 0}));

  const std::string coff_ints = "COFF\n2 0 0\n0 0 0 255 128 0 255\n1 1 1 10 20 300\n";
  const PointModel ci = read_off_from_buffer(coff_ints, "ci.off");
  ASSERT_TRUE(ci.has_colors());
  EXPECT_EQ(ci.red, (std::vector<std::uint8_t>{255, 10}));
  EXPECT_EQ(ci.green, (std::vector<std::uint8_t>{128, 20}));
  EXPECT_EQ(ci.blue, (std::vector<std::uint8_t>{0, 255}));  // 300 clamps

  const std::string cnoff_floats = "CNOFF\n1 0\n1 2 3 0 0 1 1.0 0.5 0 1\n";
  const PointModel cf = read_off_from_buffer(cnoff_floats, "cf.off");
  ASSERT_TRUE(cf.has_normals());
  EXPECT_EQ(cf.red[0], 255);
  EXPECT_EQ(cf.green[0], 128);
  EXPECT_EQ(cf.blue[0], 0);

  const std::string stoff = "STOFF\n1 0 0\n1 2 3 0.25 0.75\n";
  EXPECT_EQ(read_off_from_buffer(stoff, "st.off").position(0), (Vec3{1, 2, 3}));

  const std::string plain_with_colours = "OFF\n1 0 0\n1 2 3 0.1 0.2 0.3 1\n";
  const PointModel p = read_off_from_buffer(plain_with_colours, "p.off");
  EXPECT_FALSE(p.has_colors());
  EXPECT_EQ(p.position(0), (Vec3{1, 2, 3}));
}

TEST(OffReader, EmptyMeshIsAnEmptyModel) { EXPECT_TRUE(read_off_from_buffer("OFF\n0 0 0\n", "e.off").empty()); }

TEST(OffReader, MalformedFilesNameLineAndProblem) {
  expect_off_error("", "bad.off: line 1: empty file: missing 'OFF' header keyword");
  expect_off_error("PLY\n1 0 0\n0 0 0\n", "bad.off: line 1: missing 'OFF' header keyword (found 'PLY')");
  expect_off_error("4OFF\n1 0 0\n0 0 0 0\n", "bad.off: line 1: unsupported OFF variant '4OFF'");
  expect_off_error("OFF\n", "bad.off: line 2: missing vertex and face counts");
  expect_off_error("OFF\nthree 1 0\n", "bad.off: line 2: bad vertex count 'three'");
  expect_off_error("OFF\n3 -1 0\n", "bad.off: line 2: bad face count '-1'");
  expect_off_error("OFF\n3\n", "bad.off: line 2: missing face count");
  expect_off_error("OFF\n1 0 x\n0 0 0\n", "bad.off: line 2: bad edge count 'x'");
  expect_off_error("OFF\n1 0 0 7\n0 0 0\n", "bad.off: line 2: unexpected text after");
  expect_off_error("OFF\n100000 0 0\n0 0 0\n", "bad.off: line 2: vertex count 100000 is more than the file can hold");
  expect_off_error("OFF\n3 0 0\n0 0 0\n# comment\n1 1 1\n",
                   "bad.off: line 6: file truncated: expected 3 vertices, read 2");
  expect_off_error("OFF\n2 0 0\n0 0 0\n1 one 1\n", "bad.off: line 4: 'one' is not a number (y of vertex 1)");
  expect_off_error("OFF\n2 0 0\n0 0 0\n1 1\n", "bad.off: line 4: too few values for vertex 1: no z");
  expect_off_error("NOFF\n1 0 0\n0 0 0 1 0\n", "bad.off: line 3: too few values for vertex 0: no nz");
  expect_off_error("COFF\n1 0 0\n0 0 0 1 0\n", "bad.off: line 3: too few values for vertex 0: no colour");
  expect_off_error("OFF\n1 0 0\nnan 0 0\n", "bad.off: line 3: non-finite coordinate in vertex 0");
  expect_off_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                   "bad.off: line 7: file truncated: expected 2 faces, read 1");
  expect_off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                   "bad.off: line 6: face 0 refers to vertex 3, but there are only 3 vertices");
  expect_off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "refers to vertex -1");
  expect_off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",
                   "bad.off: line 6: face 0 lists 4 corners but the line has only 3 indices");
  expect_off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "'1.5' is not a vertex index (face 0)");
  expect_off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nthree 0 1 2\n", "bad corner count 'three' for face 0");
}

TEST(OffFuzz, SeededCorruptionIsRefusedCleanly) {
  const std::string base =
      "OFF\n# fuzz base\n6 4 0\n0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 2 0\n-1 1 0\n"
      "3 0 1 2\n4 0 2 3 4\n5 0 1 2 3 4 255 0 0\n3 5 4 3\n";
  std::mt19937 rng(99);
  int accepted = 0;
  for (int iteration = 0; iteration < 3000; ++iteration) {
    std::string text = base;
    for (int e = 0; e < 2; ++e) {
      const std::size_t at = rng() % text.size();
      const char replacement[] = {'0', '9', '-', '.', ' ', '\n', '#', 'x', 'e', '\0'};
      text[at] = replacement[rng() % std::size(replacement)];
    }
    if (rng() % 4 == 0) text.resize(rng() % text.size());
    try {
      const PointModel m = read_off_from_buffer(text, "fuzz.off");
      EXPECT_NO_THROW(m.validate()) << "iteration " << iteration;
      ++accepted;
    } catch (const ModelFileError&) {
    }  // anything else fails the test
  }
  EXPECT_GT(accepted, 100);
}

// ------------------------------------------------------------------------------------------
// XYZ

TEST(XyzReader, PositionsWithCommentsBlankLinesAndCrLf) {
  const std::string text = "# exported points\n\n1 2 3\r\n  -4.5\t5e-1 6 # trailing comment\n\n7 8 9";
  const PointModel m = read_xyz_from_buffer(text, "p.xyz");
  ASSERT_EQ(m.size(), 3u);
  EXPECT_FALSE(m.has_normals());
  EXPECT_EQ(m.position(1), (Vec3{-4.5, 0.5, 6}));
  EXPECT_EQ(m.position(2), (Vec3{7, 8, 9}));
}

TEST(XyzReader, PositionsAndNormals) {
  const PointModel m = read_xyz_from_buffer("0 0 0 0 0 1\n1 1 1 1 0 0\n", "n.xyz");
  ASSERT_EQ(m.size(), 2u);
  ASSERT_TRUE(m.has_normals());
  EXPECT_EQ(m.normal(1), (Vec3{1, 0, 0}));
  EXPECT_NO_THROW(m.validate());
}

TEST(XyzReader, EmptyAndCommentOnlyFilesAreEmptyModels) {
  EXPECT_TRUE(read_xyz_from_buffer("", "e.xyz").empty());
  EXPECT_TRUE(read_xyz_from_buffer("# nothing\n\n", "e.xyz").empty());
}

TEST(XyzReader, MalformedFilesNameLineAndProblem) {
  expect_xyz_error("1 2\n", "bad.xyz: line 1: expected 3 values (x y z) or 6 (x y z nx ny nz), found 2");
  expect_xyz_error("1 2 3 4\n", "line 1: expected 3 values (x y z) or 6 (x y z nx ny nz), found 4");
  expect_xyz_error("# head\n1 2 3\n1 2 3 0 0 1\n", "bad.xyz: line 3: expected 3 values like line 2, found 6");
  expect_xyz_error("1 2 3\n4 five 6\n", "bad.xyz: line 2: 'five' is not a number (y of point 1)");
  expect_xyz_error("1 2 3 0 0 1\n4 5 6 0 0 one\n", "line 2: 'one' is not a number (nz of point 1)");
  expect_xyz_error("1 2 3\ninf 0 0\n", "bad.xyz: line 2: non-finite 'x' in point 1");
  expect_xyz_error("5210\n1 2 3\n", "line 1: expected 3 values (x y z) or 6 (x y z nx ny nz), found 1");
}

TEST(XyzWriter, RoundTripsFloatsExactly) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> any(-1e6F, 1e6F);
  PointModel model;
  model.resize(500, true, false);
  for (std::size_t i = 0; i < model.size(); ++i) {
    model.x[i] = any(rng);
    model.y[i] = any(rng) * 1e-9F;
    model.z[i] = i == 0 ? -0.0F : any(rng) * 1e11F;  // up to 1e17, below kMaxCoordinate
    model.nx[i] = any(rng);
    model.ny[i] = 0.1F;
    model.nz[i] = std::numeric_limits<float>::denorm_min();
  }
  const PointModel back = read_xyz_from_buffer(write_xyz_to_buffer(model), "rt.xyz");
  ASSERT_EQ(back.size(), model.size());
  for (std::size_t i = 0; i < model.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(back.x[i]), std::bit_cast<std::uint32_t>(model.x[i]));
    ASSERT_EQ(std::bit_cast<std::uint32_t>(back.y[i]), std::bit_cast<std::uint32_t>(model.y[i]));
    ASSERT_EQ(std::bit_cast<std::uint32_t>(back.z[i]), std::bit_cast<std::uint32_t>(model.z[i]));
    ASSERT_EQ(back.nx[i], model.nx[i]);
    ASSERT_EQ(back.nz[i], model.nz[i]);
  }
}

TEST(XyzFuzz, SeededCorruptionIsRefusedCleanly) {
  const std::string base = "# fuzz\n1 2 3 0 0 1\n-4 5.5 6e2 1 0 0\n\n7 8 9 0 1 0\n";
  std::mt19937 rng(5);
  for (int iteration = 0; iteration < 2000; ++iteration) {
    std::string text = base;
    const std::size_t at = rng() % text.size();
    const char replacement[] = {'0', '-', '.', ' ', '\n', '#', 'x', 'e', '\r', '\0'};
    text[at] = replacement[rng() % std::size(replacement)];
    if (rng() % 3 == 0) text.resize(rng() % text.size());
    try {
      const PointModel m = read_xyz_from_buffer(text, "fuzz.xyz");
      EXPECT_NO_THROW(m.validate()) << "iteration " << iteration;
    } catch (const ModelFileError&) {
    }
  }
}

// ------------------------------------------------------------------------------------------
// Real scans, when the fetch script has put them under data/scans (optional).

struct RealScan {
  const char* file;
  std::size_t points;
  std::size_t triangles;
  bool normals;
};

void check_real_scan(const RealScan& scan) {
  const std::string path = std::string(SCULPT_SOURCE_DIR "/data/scans/") + scan.file;
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << path << " is absent (run the scan fetch script to get it)";
  }
  const PointModel m = read_model(path);
  EXPECT_EQ(m.size(), scan.points);
  EXPECT_EQ(m.triangles.size(), 3 * scan.triangles);
  EXPECT_EQ(m.has_normals(), scan.normals);
  EXPECT_NO_THROW(m.validate());
}

TEST(OffRealScan, Bunny) { check_real_scan({"bunny00.off", 37706, 75408, false}); }
TEST(OffRealScan, Armadillo) { check_real_scan({"armadillo.off", 26002, 52000, false}); }
TEST(XyzRealScan, Kitten) { check_real_scan({"kitten.xyz", 5210, 0, true}); }

}  // namespace
}  // namespace sculpt::deform
