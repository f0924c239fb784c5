#include "number_text.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

namespace sculpt::deform {
namespace {

// from_chars refuses a leading '+', which some writers emit; accept exactly one.
std::string_view without_plus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  return token;
}

// from_chars reports result_out_of_range both for overflow and for underflow and leaves the
// value alone, so decide which from the decimal exponent of the leading significant digit:
// out-of-range values are so far from 1 that the sign of that exponent settles it.
bool overflows(std::string_view token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '-' || token[i] == '+')) ++i;
  long long magnitude = 0;  // decimal exponent of the leading significant digit, without 'e'
  bool seen_point = false;
  bool seen_digit = false;
  for (; i < token.size() && token[i] != 'e' && token[i] != 'E'; ++i) {
    const char c = token[i];
    if (c == '.') {
      seen_point = true;
    } else if (!seen_digit && c == '0') {
      if (seen_point) --magnitude;
    } else if (!seen_digit) {
      seen_digit = true;
      magnitude = seen_point ? magnitude - 1 : 0;
    } else if (!seen_point) {
      ++magnitude;
    }
  }
  long long exponent = 0;
  if (i < token.size()) {
    ++i;
    bool negative = false;
    if (i < token.size() && (token[i] == '-' || token[i] == '+')) negative = token[i++] == '-';
    for (; i < token.size(); ++i) {
      // Saturate: the exponent only needs to be compared with a few hundred.
      if (exponent < 1'000'000'000) exponent = exponent * 10 + (token[i] - '0');
    }
    if (negative) exponent = -exponent;
  }
  return magnitude + exponent > 0;
}

template <typename Real>
bool parse_real(std::string_view token, Real& value) {
  token = without_plus(token);
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
  Real parsed{};
  const auto [ptr, ec] = std::from_chars(token.data(), end, parsed);
  if (ptr != end) return false;
  if (ec == std::errc::result_out_of_range) {
    const bool negative = token[0] == '-';
    const Real magnitude = overflows(token) ? std::numeric_limits<Real>::infinity() : Real(0);
    value = negative ? -magnitude : magnitude;
    return true;
  }
  if (ec != std::errc()) return false;
  value = parsed;
  return true;
}

template <typename Int>
bool parse_integer(std::string_view token, Int& value) {
  token = without_plus(token);
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

bool parse_float(std::string_view token, float& value) { return parse_real(token, value); }
bool parse_double(std::string_view token, double& value) { return parse_real(token, value); }
bool parse_int64(std::string_view token, std::int64_t& value) { return parse_integer(token, value); }
bool parse_uint64(std::string_view token, std::uint64_t& value) {
  return parse_integer(token, value);  // from_chars refuses a '-' for unsigned types
}

void append_float(std::string& out, float value) {
  char buffer[32];
  // Without a format argument to_chars gives the shortest text that round-trips exactly.
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;  // 32 characters always suffice for a float
  out.append(buffer, ptr);
}

void append_uint(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;
  out.append(buffer, ptr);
}

}  // namespace sculpt::deform
