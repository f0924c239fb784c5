#pragma once
// The check of every numeric option: a finite number within its range, refused otherwise with
// the range printed by %g. CLI11's own Range and PositiveNumber let NaN through (every
// comparison with NaN is false: `--duration nan` never stopped) and print their bounds with
// %f (the largest double as 309 digits).

#include <string>

namespace CLI {  // NOLINT(readability-identifier-naming): CLI11's own
class Validator;
}

namespace sculpt::tools {

/// A finite number in [lo, hi], either end open when its flag says so. The message CLI11 prints
/// after "--option: " reads "must be a finite number in (0, 3.1536e+07] (seconds: at most a
/// year), got nan"; `note` is the parenthesis, left out when empty.
CLI::Validator finite_in(double lo, bool lo_open, double hi, bool hi_open, const std::string& note = {});

/// A whole number in [lo, hi], written in decimal. CLI11 reads "-1" into an unsigned option as
/// 2^64 - 1 and clamps an overflowing one to the type's largest, so an index option checked by
/// CLI::Range alone took -1 and 1e21 as valid; this reads the text itself. The message reads
/// "must be a whole number in [1, 9223372036854775807], got -1".
CLI::Validator whole_in(long long lo, long long hi);

/// A finite number in (0, hi].
CLI::Validator positive_up_to(double hi, const std::string& note = {});

}  // namespace sculpt::tools
