#pragma once
// Which model a session ran on: its point count and a hash of its positions. A session log
// names the model it was recorded on, so replay can tell the recording model (or the full model
// a reduced set was drawn from) from any other before it applies a single event.

#include <cstddef>
#include <cstdint>
#include <string>

#include "sculpt/deform/point_model.hpp"

namespace sculpt::deform {

struct ModelIdentity {
  std::size_t points = 0;
  std::uint64_t hash = 0;  ///< FNV-1a 64 over the positions, see model_identity()

  bool operator==(const ModelIdentity&) const = default;
};

/// FNV-1a 64 over every point's x, y, z as IEEE-754 single-precision bytes, little-endian, in
/// point order. Positions only: normals may be repaired or re-estimated on load and colours do
/// not take part in sculpting, so neither changes which model it is.
ModelIdentity model_identity(const PointModel& model) noexcept;

/// "3203 points, hash 0x0123456789abcdef", for messages.
std::string describe(const ModelIdentity& identity);

}  // namespace sculpt::deform
