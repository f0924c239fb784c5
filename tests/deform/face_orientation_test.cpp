// Consistent face winding: checked against the geometry of closed solids, whose outward face
// normals are known independently (an octahedron about the origin: every face's normal points
// away from the centre).
#include <gtest/gtest.h>

#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "sculpt/deform/face_orientation.hpp"
#include "sculpt/deform/normals.hpp"

namespace sculpt::deform {
namespace {

// The octahedron of the six unit axis points, wound outward (counter-clockwise seen from
// outside), shifted by `centre` and scaled by `size`; its vertices appended after `model`'s.
void add_octahedron(PointModel& model, const Vec3& centre, double size) {
  const auto base = static_cast<std::uint32_t>(model.size());
  for (const Vec3& v : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    model.push_back(centre + v * size);
  }
  const std::uint32_t faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                     {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& f : faces) {
    for (std::uint32_t v : f) model.triangles.push_back(base + v);
  }
}

Vec3 face_normal(const PointModel& m, std::size_t f) {
  const Vec3 a = m.position(m.triangles[3 * f]);
  return cross(m.position(m.triangles[3 * f + 1]) - a, m.position(m.triangles[3 * f + 2]) - a);
}

Vec3 face_centre(const PointModel& m, std::size_t f) {
  return (m.position(m.triangles[3 * f]) + m.position(m.triangles[3 * f + 1]) + m.position(m.triangles[3 * f + 2])) *
         (1.0 / 3.0);
}

void reverse(PointModel& m, std::size_t f) { std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]); }

// How many faces point away from `centre` (the outward ones of a convex solid about it).
std::size_t outward_faces(const PointModel& m, const Vec3& centre, std::size_t first, std::size_t count) {
  std::size_t out = 0;
  for (std::size_t f = first; f < first + count; ++f) out += dot(face_normal(m, f), face_centre(m, f) - centre) > 0.0;
  return out;
}

TEST(FaceOrientation, TheOutwardOctahedronIsOutwardToBeginWith) {
  PointModel m;
  add_octahedron(m, {}, 1.0);
  ASSERT_EQ(outward_faces(m, {}, 0, 8), 8u) << "the fixture itself";
  const FaceOrientation r = orient_faces(m);
  EXPECT_EQ(r.turned, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.conflicts, 0u);
}

// The unit octahedron with `reversed` faces wound inward, rewound: how many turned, and how
// many faces then point outward.
std::pair<std::size_t, std::size_t> rewind_octahedron(std::initializer_list<std::size_t> reversed) {
  PointModel m;
  add_octahedron(m, {}, 1.0);
  for (std::size_t f : reversed) reverse(m, f);
  const FaceOrientation r = orient_faces(m);
  return {r.turned, outward_faces(m, {}, 0, 8)};
}

TEST(FaceOrientation, FacesWoundAgainstTheirNeighboursTurnAndOnlyThey) {
  EXPECT_EQ(rewind_octahedron({1, 6}), std::make_pair(std::size_t{2}, std::size_t{8}));
}

TEST(FaceOrientation, AMajorityWindsThePiece) {
  // Five of eight inward: the piece is taken as meant inward (a cavity wall), the three
  // outward ones turn to agree.
  EXPECT_EQ(rewind_octahedron({0, 2, 3, 5, 7}), std::make_pair(std::size_t{3}, std::size_t{0}));
}

TEST(FaceOrientation, AHollowShellKeepsItsCavityWallFacingTheCavity) {
  // Two nested, unconnected octahedra: the outer wound outward, the inner toward the centre
  // (the cavity), as the material's surface is; one face of each wound wrongly.
  PointModel m;
  add_octahedron(m, {}, 1.0);
  add_octahedron(m, {}, 0.8);
  for (std::size_t f = 8; f < 16; ++f) reverse(m, f);
  reverse(m, 3);
  reverse(m, 12);
  const FaceOrientation r = orient_faces(m);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.turned, 2u);
  EXPECT_EQ(outward_faces(m, {}, 0, 8), 8u);
  EXPECT_EQ(outward_faces(m, {}, 8, 8), 0u);
}

TEST(FaceOrientation, NormalsFromMixedFacesPointOutward) {
  // The finding: vertex normals summed over faces of mixed winding cancel or point inward.
  PointModel m;
  add_octahedron(m, {0.5, -0.25, 2.0}, 1.0);
  reverse(m, 0);
  reverse(m, 5);
  const FaceOrientation r = compute_normals_from_faces(m);
  EXPECT_EQ(r.turned, 2u);
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 out = normalized(m.position(i) - Vec3{0.5, -0.25, 2.0});
    EXPECT_GT(dot(m.normal(i), out), 0.999) << "vertex " << i;
  }
}

TEST(FaceOrientation, AnEdgeOfThreeFacesIsAConflictNotACrash) {
  PointModel m;
  for (const Vec3& v : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}}) m.push_back(v);
  m.triangles = {0, 1, 2, 0, 1, 3, 1, 0, 4};  // edge 0-1 in three triangles
  const FaceOrientation r = orient_faces(m);
  EXPECT_EQ(r.conflicts, 1u);
  EXPECT_EQ(r.components, 3u) << "a non-manifold edge is not crossed";
  EXPECT_EQ(r.turned, 0u);
}

TEST(FaceOrientation, AMobiusStripCannotBeWoundAndSaysSo) {
  // Six triangles round a strip with one half twist: no winding agrees across every edge.
  PointModel m;
  for (int k = 0; k < 6; ++k) m.push_back({static_cast<double>(k), 0.0, 0.0});
  // Quads (k, k+1) x (top, bottom) joined with the last one crossed over.
  const std::uint32_t top[3] = {0, 1, 2}, bottom[3] = {3, 4, 5};
  m.triangles = {top[0], bottom[0], top[1],    top[1], bottom[0], bottom[1], top[1],    bottom[1], top[2],
                 top[2], bottom[1], bottom[2], top[2], bottom[2], bottom[0], bottom[0], bottom[2], top[0]};
  const FaceOrientation r = orient_faces(m);
  EXPECT_GE(r.conflicts, 1u);
}

TEST(FaceOrientation, IndicesOutOfRangeAreRefusedNamingTheTriangle) {
  PointModel m;
  add_octahedron(m, {}, 1.0);
  m.triangles[3 * 4 + 2] = 99;
  try {
    orient_faces(m);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 4"), std::string::npos) << e.what();
  }
  m.triangles.push_back(0);
  EXPECT_THROW(orient_faces(m), std::invalid_argument);
}

}  // namespace
}  // namespace sculpt::deform
