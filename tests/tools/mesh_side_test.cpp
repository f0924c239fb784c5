// The sweep's mesh oracle against truths of its own: a sphere's hull winds once round its
// inside and not at all round its outside, the distance to a triangle is the least distance to
// its sampled points, a bent sheet's side is the side of its height function, and a dent pushed
// into the hull leaves its hollow outside and the material under it inside.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "mesh_side.hpp"
#include "sculpt/deform/generators.hpp"
#include "surface_mesh.hpp"

namespace sculpt::tools::check {
namespace {

using deform::Vec3;

// Unit directions spread over the sphere (a spiral other than the model's own).
std::vector<Vec3> directions(int n) {
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(1.0 - z * z), phi = 2.4 * i + 0.3;
    out.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return out;
}

TEST(MeshSideOracle, SphereHullWindsOnceInsideAndNotOutside) {
  const deform::PointModel sphere = deform::make_sphere(3203);
  const SurfaceMesh hull = convex_hull_mesh(sphere);
  MeshSideOracle oracle(hull.triangles, sphere.size());
  ASSERT_TRUE(oracle.closed());
  for (const Vec3& d : directions(60)) {
    const MeshSide in = oracle.side(sphere, d * 0.5);
    EXPECT_NEAR(in.winding, 1.0, 1e-9);
    EXPECT_TRUE(in.inside);
    EXPECT_NEAR(in.side, -0.5, 2e-3);  // the hull's facets are within ~s^2/8 of the sphere
    const MeshSide out = oracle.side(sphere, d * 1.5);
    EXPECT_NEAR(out.winding, 0.0, 1e-9);
    EXPECT_FALSE(out.inside);
    EXPECT_NEAR(out.side, 0.5, 2e-3);
  }
  EXPECT_NEAR(oracle.side(sphere, {}).winding, 1.0, 1e-9);  // the centre itself
}

TEST(MeshSideOracle, HullIsOrientedOutwardAndUsesEveryPoint) {
  const deform::PointModel sphere = deform::make_sphere(3203);
  const SurfaceMesh hull = convex_hull_mesh(sphere);
  EXPECT_EQ(hull.unused_points, 0u);                              // a sphere's points are all extreme
  EXPECT_EQ(hull.triangles.size(), 3 * (2 * sphere.size() - 4));  // Euler: F = 2V - 4
  double volume = 0.0;
  for (std::size_t t = 0; t < hull.triangles.size(); t += 3) {
    const Vec3 a = sphere.position(hull.triangles[t]), b = sphere.position(hull.triangles[t + 1]),
               c = sphere.position(hull.triangles[t + 2]);
    EXPECT_GT(dot(cross(b - a, c - a), a + b + c), 0.0) << "triangle " << t / 3 << " faces the centre";
    volume += dot(a, cross(b, c)) / 6.0;
  }
  EXPECT_NEAR(volume, 4.0 / 3.0 * std::numbers::pi, 0.01);  // a polyhedron just inside the sphere
}

TEST(ClosestOnTriangle, ClosedFormsInEachRegion) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 1, 0};
  using Feature = TriangleClosest::Feature;
  // Face: straight above an interior point.
  TriangleClosest x = closest_on_triangle({0.5, 0.25, 0.7}, a, b, c);
  EXPECT_EQ(x.feature, Feature::kFace);
  EXPECT_NEAR(norm(x.point - Vec3{0.5, 0.25, 0}), 0.0, 1e-15);
  // Vertex b: beyond it along both its edges.
  x = closest_on_triangle({3, -1, 0.5}, a, b, c);
  EXPECT_EQ(x.feature, Feature::kVertex);
  EXPECT_EQ(x.index, 1);
  EXPECT_NEAR(norm(x.point - b), 0.0, 1e-15);
  // Edge bc: the line x/2 + y = 1; q off it in the plane by h along its normal, and up by 0.3.
  const Vec3 on_bc{1.0, 0.5, 0}, out_bc = deform::normalized({1, 2, 0});
  x = closest_on_triangle(on_bc + out_bc * 0.4 + Vec3{0, 0, 0.3}, a, b, c);
  EXPECT_EQ(x.feature, Feature::kEdge);
  EXPECT_EQ(x.index, 1);
  EXPECT_NEAR(norm(x.point - on_bc), 0.0, 1e-12);
  // Edge ab (y = 0), below it.
  x = closest_on_triangle({1.2, -0.5, -0.1}, a, b, c);
  EXPECT_EQ(x.feature, Feature::kEdge);
  EXPECT_EQ(x.index, 0);
  EXPECT_NEAR(norm(x.point - Vec3{1.2, 0, 0}), 0.0, 1e-15);
}

TEST(ClosestOnTriangle, DistanceIsTheLeastOverSampledPoints) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random_point = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  constexpr int kSteps = 200;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = random_point(), b = random_point(), c = random_point();
    const Vec3 q = random_point() * 1.5;
    double sampled = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const Vec3 p = a + (b - a) * (double(i) / kSteps) + (c - a) * (double(j) / kSteps);
        sampled = std::min(sampled, norm(q - p));
      }
    }
    const TriangleClosest x = closest_on_triangle(q, a, b, c);
    const double exact = norm(q - x.point);
    // Never farther than a sample (it is the minimum), never nearer than the samples' spacing allows.
    const double longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_GE(exact, sampled - longest / kSteps) << "trial " << trial;
  }
}

// A sheet z = height(x, y) on an 21 x 21 grid of pitch 0.05, meshed in its plane, outside +z.
template <typename Height>
deform::PointModel height_sheet(Height height) {
  deform::PointModel m;
  for (int j = -10; j <= 10; ++j) {
    for (int i = -10; i <= 10; ++i) m.push_back({0.05 * i, 0.05 * j, height(0.05 * i, 0.05 * j)});
  }
  return m;
}

TEST(MeshSideOracle, FlatSheetSideAboveAndBelow) {
  const deform::PointModel sheet = height_sheet([](double, double) { return 0.0; });
  MeshSideOracle up(sheet_mesh(sheet, {0, 0, 1}).triangles, sheet.size());
  MeshSideOracle down(sheet_mesh(sheet, {0, 0, -1}).triangles, sheet.size());
  EXPECT_FALSE(up.closed());
  // Over a face, a vertex and an edge: above is outside for +z, inside for -z.
  for (const Vec3& at : {Vec3{0.013, 0.021, 0}, Vec3{0.1, 0.15, 0}, Vec3{0.125, 0.1, 0}}) {
    for (double h : {0.03, -0.03}) {
      const MeshSide s = up.side(sheet, at + Vec3{0, 0, h});
      EXPECT_NEAR(s.side, h, 1e-12) << at.x << " " << at.y << " " << h;
      EXPECT_NEAR(down.side(sheet, at + Vec3{0, 0, h}).side, -h, 1e-12);
    }
  }
}

// A sharp ridge and a sharp valley: near their crease the nearest feature is an edge or a
// vertex, where one face's normal alone gives the wrong side for some points; the pseudo-normal
// must agree with the height function at every point near the sheet.
TEST(MeshSideOracle, BentSheetSideIsTheHeightFunctionsSide) {
  for (double slope : {2.5, -2.5}) {
    auto height = [slope](double x, double y) { return -slope * std::abs(x - 0.012) + 0.1 * y; };
    const deform::PointModel sheet = height_sheet(height);
    MeshSideOracle oracle(sheet_mesh(sheet, {0, 0, 1}).triangles, sheet.size());
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.2, 0.2), dz(-0.08, 0.08);
    int tested = 0;
    for (int k = 0; k < 2000; ++k) {
      const double x = u(rng), y = u(rng);
      const Vec3 q{x, y, height(x, y) + dz(rng)};
      const double above = q.z - height(x, y);
      const MeshSide s = oracle.side(sheet, q);
      if (s.distance < 1e-9) continue;  // on the sheet: no side to check
      // The mesh is the height function's graph except between the two grid columns either
      // side of the crease (x = 0 and 0.05), where it cuts the tip off: the side is checked
      // everywhere else, including right beside the mesh's two creases there.
      if (x > -1e-6 && x < 0.05 + 1e-6) continue;
      EXPECT_EQ(s.inside, above < 0.0) << "slope " << slope << " at " << x << " " << y << " " << q.z;
      ++tested;
    }
    EXPECT_GT(tested, 1000);
  }
}

TEST(MeshSideOracle, DentPushedIntoTheHullIsHollowAboveAndSolidBelow) {
  deform::PointModel sphere = deform::make_sphere(3203);
  const SurfaceMesh hull = convex_hull_mesh(sphere);  // connectivity of the undeformed points
  // Every point within 40 degrees of the pole moved toward the centre, most at the pole: a dent
  // 0.6 deep whose floor is at z = 0.4.
  const double cap = std::cos(40.0 * std::numbers::pi / 180.0);
  for (std::size_t i = 0; i < sphere.size(); ++i) {
    const Vec3 p = sphere.position(i);
    if (p.z <= cap) continue;
    const double t = (p.z - cap) / (1.0 - cap);  // 0 at the rim, 1 at the pole
    sphere.set_position(i, p * (1.0 - 0.6 * t * t));
  }
  MeshSideOracle oracle(hull.triangles, sphere.size());
  // In the hollow (above the floor, below the old surface): outside, though the undeformed
  // sphere, and any "away from the centre" rule near the floor, would call it inside.
  for (double z : {0.5, 0.7, 0.95}) {
    const MeshSide s = oracle.side(sphere, {0.0, 0.0, z});
    EXPECT_NEAR(s.winding, 0.0, 1e-9) << z;
    EXPECT_FALSE(s.inside) << z;
  }
  // Under the floor: inside, at its depth below the floor.
  const MeshSide under = oracle.side(sphere, {0.0, 0.0, 0.3});
  EXPECT_NEAR(under.winding, 1.0, 1e-9);
  EXPECT_TRUE(under.inside);
  EXPECT_NEAR(under.side, -0.1, 5e-3);
  // Beside the dent, in untouched material and outside it.
  EXPECT_TRUE(oracle.side(sphere, {0.0, 0.9, -0.2}).inside);
  EXPECT_FALSE(oracle.side(sphere, {0.0, 1.1, -0.2}).inside);
}

TEST(MeshSideOracle, RefusesBadIndices) {
  EXPECT_THROW(MeshSideOracle({0, 1}, 3), std::invalid_argument);
  EXPECT_THROW(MeshSideOracle({0, 1, 3}, 3), std::invalid_argument);
  EXPECT_THROW(MeshSideOracle({}, 3), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::tools::check
