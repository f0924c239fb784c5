#pragma once
// Byte equality of float arrays and of point models, for the tests whose truth is "the same
// bytes": two routes to one result (a pass on one thread or two, in place or beside the model,
// replayed or live) must not differ even by a rounding, and == on floats would let 0 and -0
// pass as one.

#include <cstring>
#include <vector>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::test {

inline bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

/// The positions only (x, y, z): for a copy that does not carry normals.
inline bool same_position_bytes(const deform::PointModel& a, const deform::PointModel& b) {
  return same_bytes(a.x, b.x) && same_bytes(a.y, b.y) && same_bytes(a.z, b.z);
}

/// Positions and normals.
inline bool same_bytes(const deform::PointModel& a, const deform::PointModel& b) {
  return same_position_bytes(a, b) && same_bytes(a.nx, b.nx) && same_bytes(a.ny, b.ny) && same_bytes(a.nz, b.nz);
}

}  // namespace sculpt::test
