#pragma once
// The checksum of one event of a durable log. LCM's log format carries none, so a bit flipped
// inside a well-formed field passed every check a reader makes and changed what replay applied.
// The durable log writes, after its first event and at each flush, a SCULPT_CHECK event
// (sculpt_lcm::log_check_t) with the CRC-32 of each event since the previous check; the walk
// (event_log_walk.hpp) holds events until their check and reports one that does not match as
// damage. A log with no check after its first event (written before checks, or by another
// program such as lcm-logger) is read as it always was.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt_lcm/log_check_t.hpp"

namespace sculpt::logging {

/// The most events one check covers; the durable log writes a check early rather than grow.
inline constexpr std::size_t kMaxCheckedEvents = 4096;
/// The durable log writes a check after its first event and at least every kMaxCheckedEvents
/// events after that: a log with no check among its first this many events has none (it was
/// written before checks, or by another program), even if one check in between was damaged.
inline constexpr std::size_t kEventsBeforeUnchecked = 2 * kMaxCheckedEvents + 1;

/// CRC-32 (zlib's) of an event's bytes as LCM's log format lays them out: the sync word, the
/// event number, the timestamp, the channel's and the data's lengths (big-endian), the channel,
/// the data.
std::uint32_t event_crc32(std::int64_t number, std::int64_t utime, std::string_view channel, const std::uint8_t* data,
                          std::size_t size) noexcept;

/// Decodes a SCULPT_CHECK event. False, with `error` naming the channel and the event's byte
/// offset, when it does not decode or its numbers are not a log's (a negative count or first
/// event, a count that is not its CRCs', numbers past the largest).
bool read_check(const LogEvent& event, sculpt_lcm::log_check_t& check, std::string& error);

/// The CRC-32 a check gives for event `number`, if it covers that event.
std::optional<std::uint32_t> checked_crc(const sculpt_lcm::log_check_t& check, std::int64_t number) noexcept;

}  // namespace sculpt::logging
