#include "sculpt/deform/normals.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "sculpt/deform/generators.hpp"

namespace sculpt::deform {
namespace {

double angle_degrees(const Vec3& a, const Vec3& b) {
  const double c = std::clamp(dot(normalized(a), normalized(b)), -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

// Random sign per normal: an orientation pass must undo it.
void scramble_signs(PointModel& m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution flip(0.5);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (flip(rng)) m.set_normal(i, -m.normal(i));
  }
}

TEST(Normals, PcaOnASphereIsRadialAndOutward) {
  const Vec3 c{0.3, -0.2, 0.5};
  const double r = 2.0;
  PointModel m = make_sphere(3203, r, c);
  m.clear_normals();
  estimate_normals(m);
  ASSERT_TRUE(m.has_normals());
  double total = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 truth = (m.position(i) - c) * (1.0 / r);
    const double a = angle_degrees(m.normal(i), truth);
    total += a;
    worst = std::max(worst, a);
    EXPECT_NEAR(norm(m.normal(i)), 1.0, 1e-6);
  }
  EXPECT_LT(total / static_cast<double>(m.size()), 2.0);
  EXPECT_LT(worst, 10.0);  // also: every one is outward (< 90 degrees)
}

TEST(Normals, PcaOnAPlaneIsConsistentlyVertical) {
  PointModel m = make_plane_patch(40, 0.01);
  m.clear_normals();
  estimate_normals(m);
  const float sign = m.nz[0] > 0 ? 1.0f : -1.0f;
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_GT(sign * m.nz[i], 1.0f - 1e-5f) << "point " << i;
  }
}

TEST(Normals, PcaOnBoxFaceInteriorsIsOutward) {
  const Vec3 size{1.0, 0.8, 0.6};
  const double spacing = 0.05;
  PointModel m = make_box(size, spacing);
  const PointModel truth = m;
  m.clear_normals();
  estimate_normals(m);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    // Face interior: more than two grid steps from every other face, so the neighbourhood is
    // flat.
    const Vec3 p = m.position(i);
    int near_a_face = 0;
    for (int a = 0; a < 3; ++a) near_a_face += std::abs(p[a]) > 0.5 * size[a] - 2.5 * spacing;
    if (near_a_face != 1) continue;
    ++checked;
    EXPECT_GT(dot(m.normal(i), truth.normal(i)), 0.9999) << "point " << i;
  }
  EXPECT_GT(checked, m.size() / 3);
}

TEST(Normals, FaceNormalsOfATetrahedronAreAreaWeighted) {
  // O, A, B, C with outward-wound faces. Un-normalised face normals:
  // ABC (6,3,2), OBA (0,0,-2), OCB (-6,0,0), OAC (0,-3,0). Summed per vertex and normalised:
  // O -> (-6,-3,-2)/7, A -> +x, B -> +y, C -> +z. (An unweighted average would give O the
  // direction (-1,-1,-1).)
  PointModel m;
  m.push_back({0, 0, 0});
  m.push_back({1, 0, 0});
  m.push_back({0, 2, 0});
  m.push_back({0, 0, 3});
  m.triangles = {1, 2, 3, 0, 2, 1, 0, 3, 2, 0, 1, 3};
  compute_normals_from_faces(m);
  ASSERT_TRUE(m.has_normals());
  const Vec3 want[4] = {{-6.0 / 7, -3.0 / 7, -2.0 / 7}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.nx[i], want[i].x, 1e-6) << "vertex " << i;
    EXPECT_NEAR(m.ny[i], want[i].y, 1e-6) << "vertex " << i;
    EXPECT_NEAR(m.nz[i], want[i].z, 1e-6) << "vertex " << i;
  }
}

TEST(Normals, FaceNormalsOfAnOctahedronPointAlongTheAxes) {
  PointModel m;
  for (const Vec3& p : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    m.push_back(p * 3.0);
  }
  // Each octant's face, wound so (b - a) x (c - a) points away from the centre.
  for (const std::uint32_t xi : {0u, 1u}) {
    for (const std::uint32_t yi : {2u, 3u}) {
      for (const std::uint32_t zi : {4u, 5u}) {
        const bool flip = ((xi == 1) != (yi == 3)) != (zi == 5);  // odd number of mirrors
        if (flip) {
          m.triangles.insert(m.triangles.end(), {xi, zi, yi});
        } else {
          m.triangles.insert(m.triangles.end(), {xi, yi, zi});
        }
      }
    }
  }
  compute_normals_from_faces(m);
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_GT(dot(m.normal(i), normalized(m.position(i))), 1.0 - 1e-6) << "vertex " << i;
  }
}

TEST(Normals, FacelessPointsFollowTheirFacedNeighbours) {
  // A triangulated patch wound clockwise seen from +z, so its faces point -z; a PCA normal on
  // its own would have no reason to pick -z, so unmeshed points prove they take the side of the
  // nearest meshed point.
  PointModel m = make_plane_patch(10, 0.1);
  m.clear_normals();
  for (std::uint32_t row = 0; row + 1 < 10; ++row) {
    for (std::uint32_t col = 0; col + 1 < 10; ++col) {
      const std::uint32_t a = row * 10 + col, b = a + 1, c = a + 10, d = a + 11;
      m.triangles.insert(m.triangles.end(), {a, c, b, b, c, d});
    }
  }
  // Unmeshed points beside the patch, in its plane, tilted slightly.
  const std::size_t first_extra = m.size();
  for (int i = 0; i < 10; ++i) {
    m.push_back({0.5 + 0.1 * (i % 3), -0.45 + 0.1 * i, 0.001 * i});
  }
  compute_normals_from_faces(m);
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_LT(m.nz[i], -0.99f) << "point " << i << (i >= first_extra ? " (faceless)" : "");
  }
}

TEST(Normals, NoFacesFallsBackToEstimation) {
  PointModel m = make_sphere(500);
  m.clear_normals();
  compute_normals_from_faces(m);
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_GT(dot(m.normal(i), m.position(i)), 0.9);
}

TEST(Normals, RejectsBadTriangles) {
  PointModel m = make_plane_patch(2, 1.0);
  m.triangles = {0, 1, 4};
  EXPECT_THROW(compute_normals_from_faces(m), std::invalid_argument);
  m.triangles = {0, 1};
  EXPECT_THROW(compute_normals_from_faces(m), std::invalid_argument);
}

TEST(Normals, OrientationRepairsRandomSignsOnASphere) {
  const Vec3 c{-1.0, 2.0, 0.5};
  PointModel m = make_sphere(2000, 0.5, c);
  scramble_signs(m, 17);
  orient_normals(m);
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_GT(dot(m.normal(i), m.position(i) - c), 0.0) << "point " << i;
  }
}

TEST(Normals, OrientationSeedsEveryComponent) {
  // Two spheres far apart: two components of the k-NN graph, each must come out outward.
  const Vec3 c1{0, 0, 0}, c2{10, 0, 0};
  PointModel m = make_sphere(800, 1.0, c1);
  const PointModel other = make_sphere(800, 1.0, c2);
  m.resize(1600, true, false);
  for (std::size_t i = 0; i < 800; ++i) {
    m.set_position(800 + i, other.position(i));
    m.set_normal(800 + i, other.normal(i));
  }
  scramble_signs(m, 23);
  estimate_normals(m);  // PCA, then orientation
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 c = i < 800 ? c1 : c2;
    EXPECT_GT(dot(m.normal(i), m.position(i) - c), 0.0) << "point " << i;
  }
}

TEST(Normals, ReferencePointOrientsAnOpenCap) {
  // A hemisphere-like cap (z > 0.3 of the unit sphere), open, seen by a scanner above it.
  const PointModel sphere = make_sphere(4000);
  PointModel cap;
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    if (sphere.z[i] > 0.3f) cap.push_back(sphere.position(i));
  }
  ASSERT_GT(cap.size(), 1000u);
  NormalEstimation outside;
  outside.reference = Vec3{0.0, 0.0, 5.0};
  estimate_normals(cap, outside);
  for (std::size_t i = 0; i < cap.size(); ++i) {
    EXPECT_GT(dot(cap.normal(i), cap.position(i)), 0.95) << "point " << i;  // outward, radial
    EXPECT_GT(dot(cap.normal(i), *outside.reference - cap.position(i)), 0.0);
  }
  // Seen from the centre, the same cap's normals turn inward.
  NormalEstimation inside;
  inside.reference = Vec3{};
  orient_normals(cap, inside);
  for (std::size_t i = 0; i < cap.size(); ++i) {
    EXPECT_LT(dot(cap.normal(i), cap.position(i)), -0.95) << "point " << i;
  }
}

TEST(Normals, EnsureNormalsKeepsOrComputes) {
  PointModel m = make_sphere(300);
  m.set_normal(0, {0, 0, 1});  // a deliberately odd normal that must survive
  ensure_normals(m);
  EXPECT_EQ(m.normal(0), (Vec3{0, 0, 1}));
  ensure_normals(m, /*force=*/true);
  EXPECT_GT(dot(m.normal(0), m.position(0)), 0.9);

  PointModel tetra;  // triangles present: faces win over PCA
  tetra.push_back({0, 0, 0});
  tetra.push_back({1, 0, 0});
  tetra.push_back({0, 2, 0});
  tetra.push_back({0, 0, 3});
  tetra.triangles = {1, 2, 3, 0, 2, 1, 0, 3, 2, 0, 1, 3};
  ensure_normals(tetra);
  EXPECT_NEAR(tetra.nx[0], -6.0 / 7, 1e-6);

  PointModel empty;
  ensure_normals(empty);
  EXPECT_TRUE(empty.empty());
}

TEST(Normals, OrientWithoutNormalsThrows) {
  PointModel m = make_sphere(10);
  m.clear_normals();
  EXPECT_THROW(orient_normals(m), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
