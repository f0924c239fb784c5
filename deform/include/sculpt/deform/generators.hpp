#pragma once
// Synthetic test models: the thesis's sphere, a flat patch and a box surface, all with exact
// outward normals so tests and benchmarks have a ground truth.

#include <cstddef>

#include "sculpt/deform/point_model.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::deform {

/// The thesis's test sphere: n points (default 3,203), near-uniform (Fibonacci / golden-spiral
/// lattice: point i at height 1 - (2i + 1) / n, turned by the golden angle each step), radius r,
/// centre c, outward unit normals. No triangles, no colours.
/// Throws std::invalid_argument unless radius > 0 and finite.
PointModel make_sphere(std::size_t n = 3203, double radius = 1.0, const Vec3& centre = {});

/// A flat square patch in the z = 0 plane centred at the origin: per_side x per_side points with
/// the given spacing (row-major, x fastest), normals +z. per_side == 0 gives an empty model.
/// Throws std::invalid_argument unless spacing > 0 and finite.
PointModel make_plane_patch(std::size_t per_side, double spacing);

/// The surface of an axis-aligned box centred at the origin with the given edge lengths, points
/// on a regular grid on each face, no duplicate points on shared edges or corners, outward unit
/// normals (edge and corner points: the normalised sum of the adjacent faces' normals).
/// Along each axis the spacing is adjusted to size / m, with m = max(1, round(size / spacing)),
/// so the grid lands exactly on both faces; the model has (mx+1)(my+1)(mz+1) - (mx-1)(my-1)(mz-1)
/// points. Throws std::invalid_argument unless every edge length and the spacing are > 0 and
/// finite.
PointModel make_box(const Vec3& size, double spacing);

}  // namespace sculpt::deform
