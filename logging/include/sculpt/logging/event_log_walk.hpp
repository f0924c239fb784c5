#pragma once
// Every event of a log file in order, going on past damage: the loop over EventLogReader that
// each reader of a whole log (sculpt replay, sculpt render --log) would otherwise write again,
// with the same care for where the damage was.

#include <cstdint>
#include <functional>
#include <string>

#include "sculpt/logging/event_log_reader.hpp"

namespace sculpt::logging {

/// What the walk saw of the file as a whole.
struct EventLogTotals {
  std::uint64_t file_size = 0;
  std::uint64_t skipped_bytes = 0;  ///< passed over while resynchronising (a cut tail included)
  std::uint64_t corrupt = 0;        ///< places that were damage (on_damage's calls)
  std::uint64_t failed_checks = 0;  ///< events whose bytes did not match their check (event_check.hpp)
  std::uint64_t left_out = 0;       ///< events of a checked log that no check covered (not handed on)
};

/// Reads `path` from start to end: `on_event` for each valid event, in file order, and
/// `on_damage(offset, what)` for each place that is not one, `what` being "<path>: byte offset
/// N: ..." (EventLogReader::error()). Reading resumes at the next plausible event.
/// A checked log (event_check.hpp) hands each event on once its check has come; an event that
/// does not match its check, and a run of events no check covers (their check was damaged), is
/// damage and is not handed on. The checks themselves are not handed on. What no check follows
/// (a crash's tail) is handed on as read. A log with no check among its first 8,193 events is
/// read unchecked.
/// @throw LogFileError when the file cannot be opened or read (not damage in it).
EventLogTotals for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
                              const std::function<void(std::uint64_t offset, const std::string& what)>& on_damage);

}  // namespace sculpt::logging
