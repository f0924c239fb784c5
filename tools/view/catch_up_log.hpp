#pragma once
// The durable log a live viewer fills its gaps from, read as it grows. The station appends to
// the log for as long as the viewer follows it, and a long session's log holds a tick record
// per millisecond (hundreds of megabytes an hour): reading it whole for every gap would stall
// the viewer longer each time. Each call reads only what was appended since the last one, from
// the end of the last whole event; a cut event at the end is the station's unflushed tail, read
// again next time.
//
// The durable log's checks (sculpt/logging/event_check.hpp) are verified as a whole read does:
// a collision is answered only once the check after it has come and its CRC-32 matches. The
// station writes a check before every flush, so what the file holds is checked within a flush
// interval; a collision that does not match, or whose check was lost, is damage and is never
// answered. A log whose second event is not a check has none (lcm-logger's) and is read
// unchecked.

#include <cstdint>
#include <string>
#include <vector>

#include "frame_follower.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/records.hpp"

namespace sculpt::view {

class CatchUpLog {
 public:
  explicit CatchUpLog(std::string path);

  /// The log's events for frame ids [first, last] in log order, and whether it already holds a
  /// later frame (CatchUpResult::reached). `first` is the follower's next frame, which only
  /// grows: the events before it are forgotten, and a smaller `first`, or a log that shrank (a
  /// new session under the same name), starts the reading over from the beginning.
  /// @throw logging::LogFileError when the log cannot be read at all.
  CatchUpResult events(std::int64_t first, std::int64_t last);

  /// Bytes read from the file by all calls so far: what was appended, and the tails read again.
  std::uint64_t bytes_read() const { return bytes_read_; }
  /// Places in the log that were not a valid event, a collision that did not decode or did not
  /// match its check, a check that did not decode, and each run of collisions no check covered.
  std::size_t damaged() const { return damaged_; }
  /// Collisions whose bytes did not match their check.
  std::size_t failed_checks() const { return failed_checks_; }
  /// Collisions no check covered (theirs was damaged), never answered.
  std::size_t left_out() const { return left_out_; }

 private:
  // A collision read from a checked log, waiting for its check.
  struct Unchecked {
    logging::CollisionRecord record;
    std::int64_t number = 0;  // the event's number in the log
    std::uint32_t crc = 0;    // of its bytes as read
  };
  enum class Checks { kUnknown, kYes, kNo };

  void start_over();
  void read_appended();
  void take(const logging::LogEvent& event);
  void take_check(const logging::LogEvent& event);
  void trust(const logging::CollisionRecord& record);

  std::string path_;
  std::uint64_t resume_ = 0;                    // where the first event not yet read begins
  std::vector<logging::CollisionRecord> held_;  // read, from frame id forgotten_below_ on, log order
  std::int64_t forgotten_below_ = 0;
  std::int64_t newest_ = -1;  // the largest frame id trusted (checked, or from an unchecked log)
  std::uint64_t bytes_read_ = 0;
  std::size_t damaged_ = 0, damage_answered_ = 0;
  std::size_t failed_checks_ = 0, left_out_ = 0;
  Checks checks_ = Checks::kUnknown;
  std::uint64_t events_seen_ = 0;     // valid events from the log's start
  std::vector<Unchecked> unchecked_;  // read since the last check, in log order
};

}  // namespace sculpt::view
