// Fuzzing the PLY reader with truncations and seeded random corruption of valid files.
// Whatever the bytes, read_ply_from_buffer must either return a self-consistent model or
// throw ModelFileError: never crash, never throw anything else, never hang or allocate
// without bound. Run under ASan/UBSan, this also catches out-of-bounds reads.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <random>
#include <string>
#include <typeinfo>

#include "sculpt/deform/model_io.hpp"
#include "deform/ply_encoding_label.hpp"
#include "sculpt/deform/normal_check.hpp"

namespace sculpt::deform {
namespace {

using ply_test::encoding_label;

// Appends one value in the file's encoding (ascii text or binary bytes of `type`).
class BodyWriter {
 public:
  explicit BodyWriter(PlyEncoding encoding) : encoding_(encoding) {}

  void f32(float v) {
    if (ascii()) return text("%.9g ", static_cast<double>(v));
    put(v);
  }
  void f64(double v) {
    if (ascii()) return text("%.17g ", v);
    put(v);
  }
  void u8(unsigned v) {
    if (ascii()) return text("%.0f ", static_cast<double>(v));
    put(static_cast<std::uint8_t>(v));
  }
  void i32(int v) {
    if (ascii()) return text("%.0f ", static_cast<double>(v));
    put(static_cast<std::int32_t>(v));
  }
  void end_row() {
    if (ascii()) bytes_ += '\n';
  }
  const std::string& bytes() const { return bytes_; }

 private:
  bool ascii() const { return encoding_ == PlyEncoding::kAscii; }
  void text(const char* format, double v) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, format, v);
    bytes_ += buffer;
  }
  template <typename T>
  void put(T v) {
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    const bool big = encoding_ == PlyEncoding::kBinaryBigEndian;
    if (big != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    bytes_.append(raw, sizeof(T));
  }

  PlyEncoding encoding_;
  std::string bytes_;
};

// A valid file that exercises every reader path: all vertex attributes, an extra scalar and
// an extra list in the vertex element, faces with extra properties, an unused element.
std::string rich_ply(PlyEncoding encoding) {
  constexpr int kVertices = 30;
  constexpr int kFaces = 20;
  const char* format = encoding == PlyEncoding::kAscii                ? "ascii"
                       : encoding == PlyEncoding::kBinaryLittleEndian ? "binary_little_endian"
                                                                      : "binary_big_endian";
  std::string header = std::string("ply\nformat ") + format + " 1.0\ncomment fuzz base\n";
  header += "element vertex " + std::to_string(kVertices) + "\n";
  header +=
      "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
      "property float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty uchar alpha\nproperty double confidence\n"
      "property list uchar int neighbours\n";
  header += "element face " + std::to_string(kFaces) + "\n";
  header += "property uchar flags\nproperty list uchar int vertex_indices\n";
  header += "element edge 3\nproperty int vertex1\nproperty int vertex2\nend_header\n";

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-10.0F, 10.0F);
  BodyWriter body(encoding);
  for (int i = 0; i < kVertices; ++i) {
    body.f32(coord(rng));
    body.f32(coord(rng));
    body.f32(coord(rng));
    body.f32(0.0F);
    body.f32(0.6F);
    body.f32(-0.8F);
    for (int c = 0; c < 4; ++c) body.u8(static_cast<unsigned>((i * 37 + c * 11) % 256));
    body.f64(0.5 + i);
    const int neighbours = i % 3;
    body.u8(static_cast<unsigned>(neighbours));
    for (int k = 0; k < neighbours; ++k) body.i32((i + k + 1) % kVertices);
    body.end_row();
  }
  for (int f = 0; f < kFaces; ++f) {
    body.u8(1);
    const int corners = 3 + f % 3;
    body.u8(static_cast<unsigned>(corners));
    for (int k = 0; k < corners; ++k) body.i32((f + k * 5) % kVertices);
    body.end_row();
  }
  for (int e = 0; e < 3; ++e) {
    body.i32(e);
    body.i32(e + 1);
    body.end_row();
  }
  return header + body.bytes();
}

// What a fuzz read may do: succeed with a valid model, or throw ModelFileError.
struct Outcome {
  int accepted = 0;
  int refused = 0;
  int wrong = 0;  // anything else: a bug
};

void read_one(const std::string& bytes, Outcome& outcome, const std::string& context) {
  try {
    const PointModel m = read_ply_from_buffer(bytes, "fuzz.ply");
    m.validate();  // throws std::invalid_argument if inconsistent, counted below
    // Normals come as the file has them; check_normals must turn whatever the corruption
    // left (NaN, zero, any length) into unit normals.
    PointModel checked = m;
    check_normals(checked, NormalPolicy::kReestimate, "fuzz.ply");
    for (std::size_t i = 0; i < checked.nx.size(); ++i) {
      if (!(std::abs(norm(checked.normal(i)) - 1.0) <= kUnitNormalTolerance)) {
        throw std::logic_error("check_normals left a normal that is not unit");
      }
    }
    ++outcome.accepted;
  } catch (const ModelFileError&) {
    ++outcome.refused;
  } catch (const std::exception& e) {
    if (++outcome.wrong <= 5) {
      ADD_FAILURE() << context << ": " << typeid(e).name() << ": " << e.what();
    }
  }
}

class PlyFuzz : public ::testing::TestWithParam<PlyEncoding> {};

TEST_P(PlyFuzz, BaseFileIsValid) {
  const PointModel m = read_ply_from_buffer(rich_ply(GetParam()), "base.ply");
  EXPECT_EQ(m.size(), 30u);
  EXPECT_TRUE(m.has_normals());
  EXPECT_TRUE(m.has_alpha());
  // 20 faces of 3, 4, 5 corners in turn: 7 x 1 + 7 x 2 + 6 x 3 triangles.
  EXPECT_EQ(m.triangles.size(), 3u * (7 + 14 + 18));
}

TEST_P(PlyFuzz, EveryTruncationIsRefusedCleanly) {
  const std::string base = rich_ply(GetParam());
  Outcome outcome;
  for (std::size_t length = 0; length < base.size(); ++length) {
    read_one(base.substr(0, length), outcome, "truncated to " + std::to_string(length));
  }
  EXPECT_EQ(outcome.wrong, 0);
  // Only cuts inside the final edge element's trailing whitespace can still be complete.
  EXPECT_GT(outcome.refused, static_cast<int>(base.size()) - 3);
}

TEST_P(PlyFuzz, SeededCorruptionNeverEscapesAsAnotherError) {
  const std::string base = rich_ply(GetParam());
  const std::size_t header_size = base.find("end_header\n") + 11;
  std::mt19937 rng(20240611U + static_cast<unsigned>(GetParam()));
  const unsigned char interesting_bytes[] = {0x00, 0xFF, 0x7F, 0x80, '0', '9', '-', '.',
                                             'e',  '\n', ' ',  '\r', 'n', 'i', '#', 0x01};
  const std::uint32_t interesting_words[] = {0xFFFFFFFFU, 0x7FFFFFFFU, 0x80000000U,
                                             0x7F800000U, 0x7FC00000U, 0x00010000U};
  Outcome outcome;
  constexpr int kIterations = 4000;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    std::string bytes = base;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      // Half of the edits hit the header, where one byte changes the meaning of everything.
      const std::size_t limit = rng() % 2 == 0 ? header_size : bytes.size();
      const std::size_t at = rng() % std::max<std::size_t>(limit, 1);
      if (at >= bytes.size()) continue;
      switch (rng() % 6) {
        case 0: bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8))); break;
        case 1: bytes[at] = static_cast<char>(rng() % 256); break;
        case 2: bytes[at] = static_cast<char>(interesting_bytes[rng() % std::size(interesting_bytes)]); break;
        case 3: {
          const std::uint32_t word = interesting_words[rng() % std::size(interesting_words)];
          for (std::size_t k = 0; k < 4 && at + k < bytes.size(); ++k) {
            bytes[at + k] = static_cast<char>(word >> (8 * k));
          }
          break;
        }
        case 4: bytes.erase(at, 1); break;
        default: bytes.insert(at, 1, static_cast<char>(interesting_bytes[rng() % std::size(interesting_bytes)])); break;
      }
    }
    read_one(bytes, outcome, "iteration " + std::to_string(iteration));
  }
  EXPECT_EQ(outcome.wrong, 0);
  EXPECT_EQ(outcome.accepted + outcome.refused, kIterations);
  // Both outcomes must actually occur, or the fuzzer is not reaching the body.
  EXPECT_GT(outcome.accepted, 100);
  EXPECT_GT(outcome.refused, 100);
}

// Digits spliced into the element counts: the reader must refuse them from the file size,
// without first allocating what they ask for.
TEST_P(PlyFuzz, InflatedCountsAreRefusedWithoutAllocating) {
  const std::string base = rich_ply(GetParam());
  for (const char* element : {"element vertex 30", "element face 20", "element edge 3"}) {
    for (const char* digits : {"000000", "99999999999", "4294967295", "18446744073709551615"}) {
      std::string bytes = base;
      const std::size_t at = bytes.find(element) + std::strlen(element);
      bytes.insert(at, digits);
      EXPECT_THROW(read_ply_from_buffer(bytes, "inflated.ply"), ModelFileError) << element << digits;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PlyAllEncodings, PlyFuzz,
                         ::testing::Values(PlyEncoding::kAscii, PlyEncoding::kBinaryLittleEndian,
                                           PlyEncoding::kBinaryBigEndian),
                         [](const auto& info) { return encoding_label(info.param); });

}  // namespace
}  // namespace sculpt::deform
