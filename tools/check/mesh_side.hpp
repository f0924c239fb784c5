#pragma once
// An inside/outside oracle for models that have a surface mesh: the side of a point is read off
// the triangles themselves (fixed connectivity, the model's points as they are now), so a deep
// channel whose walls touch, or a neighbourhood turned inside out by a long series of pushes,
// is still judged by what the surface encloses, not by a local plane and a guessed outside.
//
//  - A closed mesh (every edge shared by exactly two triangles): the generalized winding number
//    (the signed solid angles of all triangles seen from the point, over 4 pi); inside when it
//    is above 1/2. It counts how often the surface wraps the point, so stretched or
//    self-touching triangles in a channel do not change the answer away from them.
//  - An open mesh (a sheet): the sign of the angle-weighted pseudo-normal at the nearest
//    feature (face, edge or vertex), which for a consistently wound mesh is the side of the
//    nearest point whatever feature it lies on.
//
// Brute force over the triangles, and nothing shared with deform's index or normals: that is
// the point of an oracle.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::tools::check {

/// The point of a triangle nearest to a query, and the feature it lies on.
struct TriangleClosest {
  enum class Feature { kFace, kEdge, kVertex };
  deform::Vec3 point;
  Feature feature = Feature::kFace;
  /// kVertex: the corner (0 a, 1 b, 2 c); kEdge: the edge (0 ab, 1 bc, 2 ca).
  int index = 0;
};

/// Exact nearest point of triangle (a, b, c) to q, by the Voronoi region of q (vertex, edge or
/// face). A degenerate triangle (a segment or a point) still gives its nearest point.
TriangleClosest closest_on_triangle(const deform::Vec3& q, const deform::Vec3& a, const deform::Vec3& b,
                                    const deform::Vec3& c);

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee),
/// in (-2 pi, 2 pi]: positive when the origin is behind the triangle (its normal
/// (b - a) x (c - a) points away from the origin), so an outward-wound closed surface adds up
/// to 4 pi from inside and 0 from outside.
double solid_angle(const deform::Vec3& a, const deform::Vec3& b, const deform::Vec3& c);

struct MeshSide {
  double distance = 0.0;  ///< to the nearest triangle, unsigned
  double side = 0.0;      ///< -distance inside, +distance outside
  bool inside = false;
  double winding = 0.0;         ///< closed meshes: the generalized winding number; open: 0
  std::uint32_t triangle = 0;   ///< the nearest triangle
  deform::Vec3 closest;         ///< the nearest point of the surface
  deform::Vec3 outward_normal;  ///< open meshes: the pseudo-normal there (unit); closed: the face's
};

class MeshSideOracle {
 public:
  /// `triangles` are index triples into a model of `point_count` points, consistently wound,
  /// outward where the mesh is closed (counter-clockwise seen from outside). Throws
  /// std::invalid_argument when the count is not a multiple of 3, empty, or an index is out of
  /// range.
  MeshSideOracle(std::vector<std::uint32_t> triangles, std::size_t point_count);

  /// The side of q against the mesh with `model`'s current positions (model.size() must be the
  /// point count given at construction).
  MeshSide side(const deform::PointModel& model, const deform::Vec3& q);

  /// Every edge shared by exactly two triangles.
  bool closed() const { return closed_; }
  std::size_t triangle_count() const { return triangles_.size() / 3; }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }

 private:
  deform::Vec3 face_normal(std::size_t t) const;  // unit, from relative_ (zero when degenerate)
  deform::Vec3 pseudo_normal(std::size_t t, const TriangleClosest& c) const;

  std::vector<std::uint32_t> triangles_;
  std::size_t point_count_ = 0;
  bool closed_ = false;
  // Open meshes: for each edge (smaller index << 32 | larger), the triangles sharing it, as a
  // sorted list searched by edge key; for each vertex, its triangles (offsets into one array).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edge_triangles_;
  std::vector<std::uint32_t> vertex_offsets_, vertex_triangles_;
  // Per query: every point relative to q, and its length (each vertex is shared by ~6 triangles).
  std::vector<deform::Vec3> relative_;
  std::vector<double> length_;
};

}  // namespace sculpt::tools::check
