#pragma once
// Parsing of the command line's vector arguments ("X,Y,Z" and "X0,Y0,Z0:X1,Y1,Z1").

#include <optional>
#include <string>
#include <string_view>

#include "sculpt/deform/contact.hpp"
#include "sculpt/deform/vec3.hpp"

namespace sculpt::tools {

/// Parses "X,Y,Z" (finite numbers); an error message names what is wrong, or is empty.
std::optional<deform::Vec3> parse_vec3(std::string_view text, std::string& error);

/// Parses one --contact "X0,Y0,Z0:X1,Y1,Z1": the probe before (outside) and after (pressed in).
std::optional<deform::ProbeMotion> parse_contact(std::string_view text, std::string& error);

}  // namespace sculpt::tools
