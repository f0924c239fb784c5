#include "coordinate_range.hpp"

#include <cmath>
#include <sstream>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

std::string coordinate_range_problem(float x, float y, float z, const char* noun, std::size_t index) {
  const float values[3] = {x, y, z};
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    // Written so that NaN fails too.
    if (std::fabs(static_cast<double>(values[k])) < kMaxCoordinate) continue;
    std::ostringstream text;  // %g-style, as the limit is written
    text << "'" << names[k] << "' = " << values[k] << " in " << noun << " " << index
         << " is out of range (coordinates must be finite and below " << kMaxCoordinate << " in magnitude)";
    return text.str();
  }
  return {};
}

}  // namespace sculpt::deform
