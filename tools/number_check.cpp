#include "number_check.hpp"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <system_error>

#include "sculpt/base/number_text.hpp"

namespace sculpt::tools {

CLI::Validator finite_in(double lo, bool lo_open, double hi, bool hi_open, const std::string& note) {
  const std::string range = std::string(lo_open ? "(" : "[") + base::number_text(lo) + ", " + base::number_text(hi) +
                            (hi_open ? ")" : "]") + (note.empty() ? std::string() : " (" + note + ")");
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        const char* begin = input.c_str();
        char* end = nullptr;
        const double value = std::strtod(begin, &end);
        if (input.empty() || end != begin + input.size()) return "expected a number, got '" + input + "'";
        const bool above = lo_open ? value > lo : value >= lo;
        const bool below = hi_open ? value < hi : value <= hi;
        // NaN fails every comparison, so finiteness is asked for by name; 1e999 reads as inf.
        if (!std::isfinite(value) || !above || !below) return "must be a finite number in " + range + ", got " + input;
        return {};
      },
      "NUMBER in " + range);
}

CLI::Validator whole_in(long long lo, long long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        long long value = 0;
        const char* end = input.data() + input.size();
        const auto [stop, error] = std::from_chars(input.data(), end, value);
        if (input.empty() || stop != end || error == std::errc::invalid_argument) {
          return "expected a whole number, got '" + input + "'";
        }
        if (error == std::errc::result_out_of_range || value < lo || value > hi) {
          return "must be a whole number in " + range + ", got " + input;
        }
        return {};
      },
      "INTEGER in " + range);
}

CLI::Validator positive_up_to(double hi, const std::string& note) { return finite_in(0.0, true, hi, false, note); }

}  // namespace sculpt::tools
