#pragma once
// The one test, and the one message, for a coordinate a model may hold (kMaxCoordinate), shared
// by PointModel::validate() and every reader so that a file and a model built in code are held
// to the same rule and reported alike.

#include <cstddef>
#include <string>

namespace sculpt::deform {

/// Empty when x, y and z are finite and below kMaxCoordinate in magnitude. Otherwise the problem
/// with the first that is not, naming the item as `noun` and `index` ("vertex", 5):
/// "'x' = 3.40282e+38 in vertex 5 is out of range (coordinates must be finite and below 1e+18 in magnitude)".
std::string coordinate_range_problem(float x, float y, float z, const char* noun, std::size_t index);

}  // namespace sculpt::deform
