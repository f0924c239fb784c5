// check_normals: the file's normals made unit or refused. The truth is the sphere's: on a
// centred sphere the outward unit normal at p is p / |p|, whatever the file said.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"
#include "sculpt/deform/normal_check.hpp"

namespace sculpt::deform {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// How far the normal at i is from the sphere's outward normal (1 - cos of the angle).
double off_radial(const PointModel& m, std::size_t i) {
  return 1.0 - dot(normalized(m.normal(i)), normalized(m.position(i)));
}

std::vector<std::uint32_t> normal_bits(const PointModel& m) {
  std::vector<std::uint32_t> bits;
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (float v : {m.nx[i], m.ny[i], m.nz[i]}) bits.push_back(std::bit_cast<std::uint32_t>(v));
  }
  return bits;
}

TEST(CheckNormals, AModelWithoutNormalsIsLeftAlone) {
  PointModel m = make_sphere(100);
  m.clear_normals();
  const NormalReport r = check_normals(m, NormalPolicy::kRefuse, "bare.xyz");
  EXPECT_EQ(r.zero_or_nonfinite, 0u);
  EXPECT_EQ(r.renormalised, 0u);
  EXPECT_FALSE(m.has_normals());
}

TEST(CheckNormals, UnitNormalsAreKeptBitForBit) {
  PointModel m = make_sphere(500);
  const std::vector<std::uint32_t> before = normal_bits(m);
  const NormalReport r = check_normals(m, NormalPolicy::kRefuse, "sphere.ply");
  EXPECT_EQ(r.zero_or_nonfinite, 0u);
  EXPECT_EQ(r.renormalised, 0u);
  EXPECT_EQ(normal_bits(m), before);
}

// OpenCV's parasaurolophus has normal lengths from 0.12 to 6.3.
TEST(CheckNormals, NormalsOfAnyLengthAreNormalisedAndCounted) {
  PointModel m = make_sphere(800);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> length(0.12, 6.3);
  std::size_t scaled = 0;
  for (std::size_t i = 0; i < m.size(); i += 2) {  // every other one; the rest stay unit
    m.set_normal(i, m.normal(i) * length(rng));
    ++scaled;
  }
  const NormalReport r = check_normals(m, NormalPolicy::kReestimate, "dino.ply");
  EXPECT_EQ(r.renormalised, scaled);
  EXPECT_EQ(r.zero_or_nonfinite, 0u);
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_NEAR(norm(m.normal(i)), 1.0, 1e-6) << i;
    EXPECT_LT(off_radial(m, i), 1e-6) << i;
  }
}

TEST(CheckNormals, LengthsWithinTheToleranceAreLeftAsTheyAre) {
  PointModel m = make_sphere(10);
  m.set_normal(3, m.normal(3) * (1.0 + 0.5 * kUnitNormalTolerance));
  const std::vector<std::uint32_t> before = normal_bits(m);
  EXPECT_EQ(check_normals(m, NormalPolicy::kReestimate, "s.ply").renormalised, 0u);
  EXPECT_EQ(normal_bits(m), before);
}

TEST(CheckNormals, ZeroAndNonFiniteNormalsAreReestimatedOutwardAndTheRestKept) {
  PointModel m = make_sphere(3203);
  const std::vector<std::size_t> zero = {0, 17, 400, 401, 402, 1000, 1600, 2222, 2900, 3100, 3150, 3202};
  const std::vector<std::size_t> nonfinite = {5, 1234, 3000};
  for (std::size_t i : zero) m.set_normal(i, {});
  m.nx[5] = kNaN;
  m.ny[1234] = kInf;
  m.nz[3000] = -kInf;
  PointModel untouched = make_sphere(3203);
  const NormalReport r = check_normals(m, NormalPolicy::kReestimate, "model.ply");
  EXPECT_EQ(r.zero_or_nonfinite, zero.size() + nonfinite.size());
  EXPECT_EQ(r.renormalised, 0u);
  std::vector<bool> bad(m.size(), false);
  for (std::size_t i : zero) bad[i] = true;
  for (std::size_t i : nonfinite) bad[i] = true;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (bad[i]) {
      EXPECT_NEAR(norm(m.normal(i)), 1.0, 1e-6) << i;
      // A PCA plane through 12 neighbours on a 3,203-point unit sphere tilts by well under 2°.
      EXPECT_LT(off_radial(m, i), 1e-3) << "vertex " << i << " re-estimated off the radial";
    } else {
      EXPECT_EQ(m.normal(i), untouched.normal(i)) << i;
    }
  }
}

// CGAL's blobby.xyz: every normal is zero, so all are estimated and oriented from scratch.
TEST(CheckNormals, AllZeroNormalsAreEstimatedAndOrientedOutward) {
  PointModel m = make_sphere(2000);
  for (std::size_t i = 0; i < m.size(); ++i) m.set_normal(i, {});
  const NormalReport r = check_normals(m, NormalPolicy::kReestimate, "blobby.xyz");
  EXPECT_EQ(r.zero_or_nonfinite, m.size());
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_LT(off_radial(m, i), 1e-3) << i;
}

TEST(CheckNormals, RefuseNamesTheFirstBadVertexAndChangesNothing) {
  PointModel m = make_sphere(50);
  m.set_normal(2, m.normal(2) * 4.0);  // would be normalised, but the refusal comes first
  m.set_normal(9, {});
  m.ny[30] = kNaN;
  const std::vector<std::uint32_t> before = normal_bits(m);
  try {
    check_normals(m, NormalPolicy::kRefuse, "scan.ply");
    FAIL() << "a zero normal was accepted";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(e.path(), "scan.ply");
    EXPECT_EQ(e.problem(), "vertex 9 has a zero normal (0, 0, 0)");
  }
  EXPECT_EQ(normal_bits(m), before);
  m.set_normal(9, {0.0, 0.0, 1.0});
  try {
    check_normals(m, NormalPolicy::kRefuse, "scan.ply");
    FAIL() << "a NaN normal was accepted";
  } catch (const ModelFileError& e) {
    EXPECT_NE(std::string(e.what()).find("scan.ply: vertex 30 has a non-finite normal"), std::string::npos) << e.what();
  }
}

TEST(CheckNormals, DescribeGroupsThousandsAndSaysNothingWhenNothingChanged) {
  EXPECT_EQ(describe(NormalReport{}), "");
  EXPECT_EQ(describe(NormalReport{12, 3400}), "12 zero or non-finite normals re-estimated, 3,400 normalised");
  EXPECT_EQ(describe(NormalReport{1, 0}), "1 zero or non-finite normal re-estimated");
  EXPECT_EQ(describe(NormalReport{0, 1}), "1 normal normalised");
  EXPECT_EQ(describe(NormalReport{0, 1234567}), "1,234,567 normals normalised");
  EXPECT_EQ(describe(NormalReport{999, 1000}), "999 zero or non-finite normals re-estimated, 1,000 normalised");
}

// The readers hand non-finite normals over as the file has them; check_normals decides.
TEST(CheckNormals, ReadersPassNonFiniteNormalsOnForTheCheck) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n"
      "1 0 0 1 0 0\n0 1 0 0 -inf 0\n";
  const std::vector<PointModel> read = {read_ply_from_buffer(ply, "n.ply"),
                                        read_off_from_buffer("NOFF\n2 0 0\n1 0 0 1 0 0\n0 1 0 nan 1 0\n", "n.off"),
                                        read_xyz_from_buffer("1 0 0 1 0 0\n0 1 0 0 nan 0\n", "n.xyz")};
  for (PointModel m : read) {
    ASSERT_TRUE(m.has_normals());
    EXPECT_FALSE(is_finite(m.normal(1)));
    EXPECT_THROW(check_normals(m, NormalPolicy::kRefuse, "n"), ModelFileError);
  }
  // Positions stay refused: a point at infinity is no point at all.
  EXPECT_THROW(read_xyz_from_buffer("1 0 0 1 0 0\ninf 1 0 0 1 0\n", "p.xyz"), ModelFileError);
}

}  // namespace
}  // namespace sculpt::deform
