#include "vector_argument.hpp"

#include <charconv>
#include <cmath>

namespace sculpt::tools {
namespace {

// Built with append rather than a chain of operator+ from a literal: GCC 12 raises a false
// -Wrestrict on the latter (GCC bug 105329).
std::string quoted(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out.append("'").append(text).append("'");
  return out;
}

}  // namespace

std::optional<deform::Vec3> parse_vec3(std::string_view text, std::string& error) {
  deform::Vec3 v;
  std::size_t start = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t comma = text.find(',', start);
    const bool last = axis == 2;
    if (last != (comma == std::string_view::npos)) {
      error = quoted(text).append(" is not three comma-separated numbers X,Y,Z");
      return std::nullopt;
    }
    const std::string_view field = text.substr(start, last ? std::string_view::npos : comma - start);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (ec != std::errc() || end != field.data() + field.size() || field.empty() || !std::isfinite(value)) {
      error = quoted(field).append(" in ").append(quoted(text)).append(" is not a finite number");
      return std::nullopt;
    }
    v[axis] = value;
    start = comma + 1;
  }
  return v;
}

std::optional<deform::ProbeMotion> parse_contact(std::string_view text, std::string& error) {
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos || text.find(':', colon + 1) != std::string_view::npos) {
    error = std::string("contact ").append(quoted(text)).append(" must be X0,Y0,Z0:X1,Y1,Z1 (before:after)");
    return std::nullopt;
  }
  const auto before = parse_vec3(text.substr(0, colon), error);
  if (!before) return std::nullopt;
  const auto after = parse_vec3(text.substr(colon + 1), error);
  if (!after) return std::nullopt;
  return deform::ProbeMotion{*before, *after, std::nullopt};
}

}  // namespace sculpt::tools
