// Faces survive: a model read with faces writes them back (PLY in every encoding, OFF), and a
// deformation moves the points while the connectivity stays as it was. The truth is a grid
// triangulated here by hand, so every index is known without reading anything back.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"
#include "deform/ply_encoding_label.hpp"

namespace sculpt::deform {
namespace {

constexpr std::size_t kPerSide = 21;
constexpr double kSpacing = 0.02;

// Two triangles per grid cell, counter-clockwise seen from +z (the patch's normals).
std::vector<std::uint32_t> grid_triangles(std::size_t per_side) {
  std::vector<std::uint32_t> t;
  for (std::uint32_t row = 0; row + 1 < per_side; ++row) {
    for (std::uint32_t col = 0; col + 1 < per_side; ++col) {
      const auto a = static_cast<std::uint32_t>(row * per_side + col);
      const auto b = a + 1;
      const auto c = static_cast<std::uint32_t>(a + per_side);
      const auto d = c + 1;
      t.insert(t.end(), {a, b, d, a, d, c});
    }
  }
  return t;
}

PointModel grid_mesh(bool normals, bool colors) {
  PointModel m = make_plane_patch(kPerSide, kSpacing);
  if (!normals) m.clear_normals();
  if (colors) {
    m.resize(m.size(), false, true);
    for (std::size_t i = 0; i < m.size(); ++i) {
      m.red[i] = static_cast<std::uint8_t>(i);
      m.green[i] = static_cast<std::uint8_t>(255 - i % 256);
      m.blue[i] = static_cast<std::uint8_t>(i * 7);
    }
  }
  m.triangles = grid_triangles(kPerSide);
  return m;
}

// Every attribute the writers write, in one comparable value.
auto written(const PointModel& m) {
  return std::tie(m.x, m.y, m.z, m.nx, m.ny, m.nz, m.red, m.green, m.blue, m.triangles);
}

void expect_same_points_and_faces(const PointModel& expected, const PointModel& actual) {
  EXPECT_EQ(actual.triangles, expected.triangles);
  EXPECT_TRUE(written(actual) == written(expected)) << "points, normals or colours differ";
}

std::string faces_file_path(const std::string& file_name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string unique = std::string("faces_") + info->name() + "_" + file_name;
  for (char& c : unique) c = c == '/' ? '_' : c;
  return ::testing::TempDir() + unique;
}

class FacesThroughPly : public ::testing::TestWithParam<PlyEncoding> {};

TEST_P(FacesThroughPly, EveryTriangleAndIndexComesBack) {
  const PointModel mesh = grid_mesh(true, true);
  ASSERT_EQ(mesh.triangles.size(), 3 * 2 * (kPerSide - 1) * (kPerSide - 1));
  const std::string bytes = write_ply_to_buffer(mesh, GetParam());
  EXPECT_NE(bytes.find("element face 800\n"), std::string::npos);
  expect_same_points_and_faces(mesh, read_ply_from_buffer(bytes, "grid.ply"));
}

TEST_P(FacesThroughPly, APointCloudGetsNoFaceElement) {
  PointModel cloud = grid_mesh(false, false);
  cloud.triangles.clear();
  const std::string bytes = write_ply_to_buffer(cloud, GetParam());
  EXPECT_EQ(bytes.find("element face"), std::string::npos);
  EXPECT_TRUE(read_ply_from_buffer(bytes, "cloud.ply").triangles.empty());
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, FacesThroughPly,
                         ::testing::Values(PlyEncoding::kAscii, PlyEncoding::kBinaryLittleEndian,
                                           PlyEncoding::kBinaryBigEndian),
                         [](const auto& info) { return ply_test::encoding_label(info.param); });

TEST(FacesThroughOff, EveryVariantKeepsPointsFacesNormalsAndColours) {
  for (const bool normals : {false, true}) {
    for (const bool colors : {false, true}) {
      const PointModel mesh = grid_mesh(normals, colors);
      const std::string text = write_off_to_buffer(mesh);
      const std::string keyword = std::string(colors ? "C" : "") + (normals ? "N" : "") + "OFF\n";
      EXPECT_EQ(text.substr(0, keyword.size() + 10), keyword + "441 800 0\n");
      expect_same_points_and_faces(mesh, read_off_from_buffer(text, "grid.off"));
    }
  }
}

TEST(FacesThroughOff, PolygonsReadAreWrittenAsTheirFannedTriangles) {
  // A quad and a pentagon, fanned from their first corner on reading.
  const std::string text = "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n-1 0.5 0\n4 0 1 2 3\n5 4 3 2 1 0\n";
  const std::vector<std::uint32_t> fanned = {0, 1, 2, 0, 2, 3, 4, 3, 2, 4, 2, 1, 4, 1, 0};
  const PointModel read = read_off_from_buffer(text, "poly.off");
  ASSERT_EQ(read.triangles, fanned);
  EXPECT_EQ(read_off_from_buffer(write_off_to_buffer(read), "again.off").triangles, fanned);
  EXPECT_EQ(read_ply_from_buffer(write_ply_to_buffer(read), "again.ply").triangles, fanned);
}

TEST(FacesThroughFiles, WriteModelChoosesOffByExtensionAndKeepsFaces) {
  const PointModel mesh = grid_mesh(true, false);
  for (const char* name : {"grid.off", "GRID.OFF", "grid.ply"}) {
    const std::string path = faces_file_path(name);
    write_model(path, mesh);
    expect_same_points_and_faces(mesh, read_model(path));
    std::filesystem::remove(path);
  }
}

TEST(FacesThroughDeformation, PointsMoveAndTheConnectivityStays) {
  PointModel mesh = grid_mesh(true, false);
  const PointModel before = mesh;
  DeformSettings settings;
  settings.kernel = {KernelKind::kKelvin, {3e7, 0.45}, 0.0};
  settings.contact.bc_radius = kSpacing;
  settings.contact.min_source_distance = 0.25 * kSpacing;
  settings.contact.guard_distance = 1.5 * kSpacing;
  Deformer deformer(mesh, settings);
  const ProbeMotion push{{0.0, 0.0, 0.05}, {0.0, 0.0, -0.03}, std::nullopt};
  const FrameReport& report = deformer.deform({&push, 1});
  ASSERT_EQ(report.collisions, 1u);
  ASSERT_GT(report.max_displacement, 0.01);
  EXPECT_EQ(mesh.triangles, before.triangles);
  EXPECT_NE(mesh.z, before.z);
  const PointModel back = read_ply_from_buffer(write_ply_to_buffer(mesh), "pressed.ply");
  expect_same_points_and_faces(mesh, back);
}

}  // namespace
}  // namespace sculpt::deform
