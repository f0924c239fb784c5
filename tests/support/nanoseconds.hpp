#pragma once
// Durations in the nanoseconds the loop's clocks count.

#include <cstdint>

namespace sculpt::test {

inline constexpr std::int64_t kMs = 1'000'000;  ///< one millisecond

}  // namespace sculpt::test
