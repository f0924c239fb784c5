// What the readers refuse about a file as a whole: anything but a regular file (before a byte is
// read), counts the file cannot hold (before anything is allocated for them), and data after
// what the header declares (which would otherwise be dropped without a word).

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

namespace fs = std::filesystem;

std::string limits_file_path(const std::string& file_name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return ::testing::TempDir() + "limits_" + info->name() + "_" + file_name;
}

// Expects `read` to throw ModelFileError whose what() is exactly `expected`.
template <typename Read>
void expect_message(Read read, const std::string& expected) {
  try {
    read();
    ADD_FAILURE() << "accepted; expected: " << expected;
  } catch (const ModelFileError& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
}

// An ascii PLY of x y z points whose header declares `count` of them, then `body`.
std::string ascii_points(const std::string& count, const std::string& body) {
  return "ply\nformat ascii 1.0\nelement vertex " + count +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + body;
}

std::string le_float(float v) {
  char raw[4];
  std::memcpy(raw, &v, 4);
  if (std::endian::native == std::endian::big) std::reverse(raw, raw + 4);
  return std::string(raw, 4);
}

TEST(ModelFileKind, ADirectoryIsRefused) {
  const std::string path = limits_file_path("folder.ply");
  fs::create_directories(path);
  expect_message([&] { read_model(path); }, path + ": cannot read: a directory, not a regular file");
  fs::remove_all(path);
}

// A FIFO would block the open until a writer came, then read for as long as it wrote.
TEST(ModelFileKind, AFifoIsRefusedWithoutWaitingForAWriter) {
  const std::string path = limits_file_path("pipe.off");
  fs::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  expect_message([&] { read_model(path); }, path + ": cannot read: a FIFO, not a regular file");
  fs::remove(path);
}

// /dev/zero never ends: read, it fills memory. A .ply name must not get it past the check.
TEST(ModelFileKind, ADeviceIsRefusedEvenBehindAModelName) {
  expect_message([] { read_ply("/dev/zero"); }, "/dev/zero: cannot read: a character device, not a regular file");
  const std::string link = limits_file_path("zero.ply");
  fs::remove(link);
  fs::create_symlink("/dev/zero", link);
  expect_message([&] { read_model(link); }, link + ": cannot read: a character device, not a regular file");
  fs::remove(link);
}

TEST(ModelFileKind, AMissingFileSaysSo) {
  const std::string path = limits_file_path("absent.xyz");
  expect_message([&] { read_model(path); }, path + ": cannot open (No such file or directory)");
}

// --- counts against the bytes left --------------------------------------------------------

TEST(DeclaredCounts, BinaryVerticesBeyondTheBytesLeftAreRefusedAtTheBodyOffset) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  const std::string bytes = header + le_float(1) + le_float(2) + le_float(3);
  // Fixed-size vertices: the reader can say exactly where the first missing one would start.
  const std::string end = std::to_string(header.size() + 12);
  expect_message([&] { read_ply_from_buffer(bytes, "lie.ply"); },
                 "lie.ply: byte offset " + end +
                     ": body truncated: expected 1000000000 vertices, read 1 (the file ends at byte " + end + ")");
}

TEST(DeclaredCounts, BinaryFacesBeyondTheBytesLeftAreRefusedNamingTheFaces) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4000000000\n"
      "property list uchar int vertex_indices\nend_header\n";
  const std::string bytes = header + le_float(0) + le_float(0) + le_float(0) + std::string(5, '\0');
  expect_message([&] { read_ply_from_buffer(bytes, "lie.ply"); },
                 "lie.ply: byte offset " + std::to_string(header.size() + 12) +
                     ": body truncated: expected 4000000000 faces, but the 5 bytes left can hold "
                     "at most 5");
}

TEST(DeclaredCounts, AsciiPlyVerticesBeyondTheTextLeftAreRefused) {
  expect_message([] { read_ply_from_buffer(ascii_points("5000000", "0 0 0\n"), "lie.ply"); },
                 "lie.ply: line 8: body truncated: expected 5000000 vertices, but the 6 bytes left "
                 "can hold at most 1");
}

TEST(DeclaredCounts, OffVerticesAndFacesBeyondTheTextLeftAreRefused) {
  expect_message([] { read_off_from_buffer("OFF\n900000000 0 0\n0 0 0\n", "lie.off"); },
                 "lie.off: line 2: vertex count 900000000 is more than the file can hold");
  expect_message([] { read_off_from_buffer("OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "lie.off"); },
                 "lie.off: line 2: face count 2000000000 is more than the rest of the file can hold");
  expect_message([] { read_off_from_buffer("OFF 3 18446744073709551615 0\n0 0 0\n1 0 0\n0 1 0\n", "lie.off"); },
                 "lie.off: line 1: face count 18446744073709551615 is more than the rest of the file can hold");
}

TEST(DeclaredCounts, TheTightestHonestCountsAreRead) {
  // Five empty faces ("0", the last without a line end) fill exactly nine bytes, and one
  // "0 0 0" vertex five: the bounds must not refuse what is there.
  const PointModel m = read_off_from_buffer("OFF\n1 5 0\n0 0 0\n0\n0\n0\n0\n0", "tight.off");
  EXPECT_EQ(m.size(), 1u);
  EXPECT_TRUE(m.triangles.empty());
}

// --- data after the declared elements -----------------------------------------------------

TEST(TrailingData, AnAsciiPlyWithMoreVerticesThanDeclaredIsRefusedAtTheFirstExtraLine) {
  expect_message([] { read_ply_from_buffer(ascii_points("2", "0 0 0\n1 0 0\n0 1 0\n"), "more.ply"); },
                 "more.ply: line 10: data after the declared elements, starting with '0' (the header "
                 "declares fewer elements than the file holds)");
}

TEST(TrailingData, AsciiPlyMayEndWithBlankAndCommentLines) {
  const std::string text = ascii_points("1", "0 0 0\n\n  \t\ncomment exported by hand\n\r\n");
  EXPECT_EQ(read_ply_from_buffer(text, "ok.ply").size(), 1u);
}

TEST(TrailingData, BinaryPlyMayEndWithANewline) {
  const std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n" +
      le_float(1) + le_float(2) + le_float(3) + "\n";
  EXPECT_EQ(read_ply_from_buffer(bytes, "ok.ply").size(), 1u);
}

TEST(TrailingData, AnOffWithMoreFacesThanDeclaredIsRefusedAtTheFirstExtraLine) {
  expect_message([] { read_off_from_buffer("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n", "more.off"); },
                 "more.off: line 7: data after the declared vertices and faces, starting with '3' (the "
                 "header's counts are fewer than the file holds)");
}

TEST(TrailingData, OffMayEndWithBlankAndCommentLines) {
  const PointModel m =
      read_off_from_buffer("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n# the end\n   # really\n", "ok.off");
  EXPECT_EQ(m.triangles.size(), 3u);
}

}  // namespace
}  // namespace sculpt::deform
