#pragma once
// Locale-independent number parsing and formatting for the text model formats, built on
// std::from_chars / std::to_chars: no iostreams, no allocation, exact round trips.

#include <cstdint>
#include <string>
#include <string_view>

namespace sculpt::deform {

/// Parses the whole token as a decimal float, correctly rounded to float. "inf" and "nan" are
/// accepted (callers decide whether non-finite values are allowed); values beyond the float
/// range become +-inf and values too small become +-0. False if the token is not a number.
bool parse_float(std::string_view token, float& value);
/// parse_float for double.
bool parse_double(std::string_view token, double& value);
/// Parses the whole token as a decimal integer; false if it is not one or does not fit.
bool parse_int64(std::string_view token, std::int64_t& value);
/// parse_int64 for non-negative integers.
bool parse_uint64(std::string_view token, std::uint64_t& value);

/// Appends the shortest decimal text that reads back (with parse_float) to exactly `value`.
void append_float(std::string& out, float value);
/// Appends an unsigned integer in decimal.
void append_uint(std::string& out, std::uint64_t value);

}  // namespace sculpt::deform
