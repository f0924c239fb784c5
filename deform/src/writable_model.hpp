#pragma once
// What every model writer checks before it writes a byte.

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

/// Throws std::invalid_argument, prefixed with `writer` ("write_ply"), when the model is
/// inconsistent (PointModel::validate) or has a non-finite normal. Non-finite normals are not
/// normals: a file the project writes never needs check_normals' repair, and other tools choke
/// on them.
void check_writable(const PointModel& model, const char* writer);

}  // namespace sculpt::deform
