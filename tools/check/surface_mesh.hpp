#pragma once
// Surface meshes for the mesh oracle (mesh_side.hpp), made from the undeformed points without
// the deformer's help: the convex hull of a convex shape's points, the Delaunay triangulation of
// a sheet in its plane. Each is an index list into the
// model's points, so the same connectivity carries the deformed points.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::tools::check {

struct SurfaceMesh {
  std::vector<std::uint32_t> triangles;  ///< index triples, wound counter-clockwise seen from outside
  std::size_t unused_points = 0;         ///< model points no triangle uses (inside the hull, duplicates)
};

/// The convex hull of the model's points (Qhull, triangulated), every triangle wound so that its
/// normal points away from the hull. Throws std::runtime_error when Qhull fails (fewer than 4
/// points, all coplanar).
SurfaceMesh convex_hull_mesh(const deform::PointModel& model);

/// The Delaunay triangulation (Qhull) of the model's points projected on the plane normal to
/// `outside`, every triangle wound so that its normal has a positive component along `outside`.
/// For a sheet whose points lie (nearly) in that plane. Throws std::runtime_error when Qhull fails.
SurfaceMesh sheet_mesh(const deform::PointModel& model, const deform::Vec3& outside);

}  // namespace sculpt::tools::check
