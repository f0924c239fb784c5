#pragma once
// Point normals: from a model's faces when it has them, otherwise estimated from the points
// themselves and oriented consistently.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sculpt/deform/face_orientation.hpp"
#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

/// Area-weighted vertex normals from model.triangles: each point's normal is the normalised sum
/// of the un-normalised cross products (b - a) x (c - a) of the faces it belongs to, so larger
/// faces weigh more and the faces' winding sets the side.
/// Points on no face (or whose face normals cancel to zero) get a PCA normal (as in
/// estimate_normals) oriented to agree with the normal of their nearest point that has one from
/// faces. If no point gets a face normal at all, this is estimate_normals(model).
/// Replaces any normals the model had. Throws std::invalid_argument on a triangle index out of
/// range or an index count that is not a multiple of 3.
/// The faces are first wound consistently (orient_faces(), which rewrites model.triangles), so
/// the side is the surface's, not each face's; what that turned is returned.
FaceOrientation compute_normals_from_faces(PointModel& model);

/// Options for estimate_normals() and orient_normals().
struct NormalEstimation {
  /// Neighbourhood size k, the point itself included (values below 3 are raised to 3).
  std::size_t neighbours = 12;
  /// Scanner position, if known: every normal is turned to face it.
  std::optional<Vec3> reference;
};

/// PCA normals: for each point, the eigenvector of the smallest eigenvalue of the 3x3 covariance
/// of its k nearest neighbours, then oriented consistently by orient_normals(). Replaces any
/// normals the model had; a no-op on an empty model.
void estimate_normals(PointModel& model, const NormalEstimation& options = {});

/// Flips the model's existing normals (signs only) into a consistent orientation:
/// with `reference` set (the scanner position, the thesis's reference point), each normal points
/// toward the reference side (dot(n, reference - p) >= 0);
/// otherwise Hoppe-style propagation along a minimum spanning tree of the symmetric k-NN graph
/// with edge weights 1 - |n_i . n_j| (so the sign is carried across nearly parallel neighbours
/// first), seeded at the point with the largest x, which is oriented +x (outward for closed
/// scans); every connected component is seeded the same way.
/// Throws std::invalid_argument if the model has no normals (and is not empty).
void orient_normals(PointModel& model, const NormalEstimation& options = {});

/// New normals for the listed points only (indices, repeats allowed), the others kept: each
/// listed point gets the PCA normal of its k = 12 nearest points (listed or not: the plane is
/// the surface's, whatever the normals say), turned to agree with the normal of its nearest
/// unlisted point, whose side is taken as settled. When every point is listed there is nothing
/// to agree with, and this is ensure_normals(model, true). A no-op for an empty list.
/// Throws std::invalid_argument if the model has no normals or an index is out of range.
void reestimate_normals(PointModel& model, const std::vector<std::uint32_t>& points);

/// Gives the model normals: from faces if it has triangles, PCA (default options) otherwise.
/// A no-op if it already has normals, unless `force`. Returns what winding the faces needed
/// (nothing when the normals did not come from faces).
FaceOrientation ensure_normals(PointModel& model, bool force = false);

}  // namespace sculpt::deform
