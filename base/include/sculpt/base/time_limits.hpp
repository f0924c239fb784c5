#pragma once
// The longest duration and timeout anything accepts, in one place for the scene parser, the
// simulated glove's script and the command line. A time is turned into int64 nanoseconds
// somewhere on its way to a clock: 1e308 s (or 1e13 ms, added to a clock) would overflow that
// and, like NaN, make a session stop at once or never. A year of sculpting and an hour of
// waiting are far beyond any session and far inside int64's 292 years of nanoseconds.

namespace sculpt::base {

/// Longest session or script: 365 days, in seconds.
inline constexpr double kMaxDurationS = 365.0 * 86400.0;
/// Longest timeout, reconnect interval, latency or flush interval: one hour, in milliseconds.
inline constexpr double kMaxTimeoutMs = 3600.0 * 1000.0;

}  // namespace sculpt::base
