#pragma once
// The durable log a live viewer fills its gaps from, read as it grows. The station appends to
// the log for as long as the viewer follows it, and a long session's log holds a tick record
// per millisecond (hundreds of megabytes an hour): reading it whole for every gap would stall
// the viewer longer each time. Each call reads only what was appended since the last one, from
// the end of the last whole event; a cut event at the end is the station's unflushed tail, read
// again next time.

#include <cstdint>
#include <string>
#include <vector>

#include "frame_follower.hpp"
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
  /// Places in the log that were not a valid event, or a collision that did not decode.
  std::size_t damaged() const { return damaged_; }

 private:
  void start_over();
  void read_appended();

  std::string path_;
  std::uint64_t resume_ = 0;                    // where the first event not yet read begins
  std::vector<logging::CollisionRecord> held_;  // read, from frame id forgotten_below_ on, log order
  std::int64_t forgotten_below_ = 0;
  std::int64_t newest_ = -1;  // the largest frame id read
  std::uint64_t bytes_read_ = 0;
  std::size_t damaged_ = 0;
};

}  // namespace sculpt::view
