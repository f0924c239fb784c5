#pragma once
// A reader of LCM's log-file format that survives damage. Written by hand rather than on
// lcm::LogFile because LCM's reader gives no byte offsets: on a bad sync word it silently
// scans ahead, and on a truncated or absurd header it just reports the end of the log, so a
// damaged edit history would be cut short without a word. This one says where and why, skips
// to the next plausible event and counts what it skipped.
//
// Format of one event (all integers big-endian), as written by lcm_eventlog_write_event:
//   u32 sync word 0xEDA1DA01, i64 event number, i64 timestamp (us), i32 channel length,
//   i32 data length, channel bytes (no terminator), data bytes.

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "sculpt/logging/lcm_lengths.hpp"

namespace sculpt::logging {

/// A log file that cannot be opened or read at all; the message names the path.
class LogFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LogEvent {
  std::uint64_t offset = 0;  ///< byte offset of the event's sync word in the file
  std::int64_t number = 0;   ///< event number as written
  std::int64_t utime = 0;    ///< timestamp, microseconds since the Unix epoch
  std::string channel;
  std::vector<std::uint8_t> data;
};

inline constexpr std::uint32_t kLogSyncWord = 0xEDA1DA01u;
inline constexpr std::size_t kLogHeaderSize = 4 + 8 + 8 + 4 + 4;
/// The byte offset just past `event` in its file: where the next event begins.
inline std::uint64_t end_of(const LogEvent& event) noexcept {
  return event.offset + kLogHeaderSize + event.channel.size() + event.data.size();
}
/// Longest channel name accepted. LCM itself allows 63 characters; a little slack keeps
/// foreign logs readable while still rejecting garbage lengths at once.
inline constexpr std::int32_t kMaxLogChannelLength = 255;

/// Reads events one by one. Lengths are checked against what is left of the file before
/// anything is allocated, so a damaged length never causes a giant allocation.
/// Not thread-safe; one reader per thread.
class EventLogReader {
 public:
  enum class Result { kEvent, kEnd, kCorrupt };

  /// Reads from byte offset `start`: 0, or the end of an event an earlier reader returned (a
  /// reader of a log that is still growing goes on from there).
  /// @throw LogFileError naming the path when the file cannot be opened or sized, or is shorter
  /// than `start`.
  explicit EventLogReader(const std::string& path, std::uint64_t start = 0);
  ~EventLogReader();
  EventLogReader(const EventLogReader&) = delete;
  EventLogReader& operator=(const EventLogReader&) = delete;

  /// kEvent: `out` holds the next event. kEnd: nothing more (further calls keep returning
  /// kEnd). kCorrupt: the bytes at the current position are not a valid event; error() says
  /// where and why ("<path>: byte offset N: ..."), `out` is unspecified, and the next call
  /// resynchronises by scanning forward for the next sync word whose header is plausible.
  /// @throw LogFileError when reading the file fails (an I/O error, not damage in it).
  Result next(LogEvent& out);

  /// The last kCorrupt's description; empty before any.
  const std::string& error() const noexcept { return error_; }
  /// The byte offset the last kCorrupt describes (where the bad bytes begin).
  std::uint64_t error_offset() const noexcept { return error_offset_; }
  /// Whether the last kCorrupt is bytes that run out (an event or header longer than what is
  /// left of the file): what a crash leaves at the end, unlike bytes that are not an event.
  bool error_is_cut() const noexcept { return error_is_cut_; }
  /// Bytes passed over while resynchronising (including a truncated tail).
  std::uint64_t skipped_bytes() const noexcept { return skipped_bytes_; }
  /// kCorrupt results so far.
  std::uint64_t corrupt_events() const noexcept { return corrupt_events_; }
  std::uint64_t file_size() const noexcept { return size_; }
  const std::string& path() const noexcept { return path_; }

 private:
  struct Header {
    std::uint32_t sync = 0;
    std::int64_t number = 0;
    std::int64_t utime = 0;
    std::int32_t channel_length = 0;
    std::int32_t data_length = 0;
  };
  Result corrupt(const std::string& what, bool cut);
  void read_at(std::uint64_t offset, void* buffer, std::size_t size);
  Header read_header(std::uint64_t offset);
  /// Empty when the event at `offset` (header already read) is well-formed, else why not (and
  /// `cut` says whether it is longer than what is left). Reads the channel name into `channel`
  /// once its length is known to be sane.
  std::string check(std::uint64_t offset, const Header& header, std::string& channel, bool& cut);
  void resynchronise();

  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0;
  std::uint64_t position_ = 0;  // offset of the next event
  bool resync_pending_ = false;
  std::string error_;
  std::uint64_t error_offset_ = 0;
  bool error_is_cut_ = false;
  std::uint64_t skipped_bytes_ = 0;
  std::uint64_t corrupt_events_ = 0;
  std::vector<std::uint8_t> scan_buffer_;
};

/// Decodes `event`'s payload as `Message`. False, with `error` naming the channel and the
/// event's byte offset, when the payload is shorter than a fingerprint, carries another type's
/// fingerprint (e.g. a tick_stats_t on the collision channel), carries an array count or string
/// length that does not fit it (checked before LCM's decoder trusts it), is too short for the
/// type, or has bytes left over after it.
template <typename Message>
bool decode(const LogEvent& event, Message& out, std::string& error) {
  const auto where = [&] { return event.channel + " event at byte offset " + std::to_string(event.offset) + ": "; };
  const std::size_t size = event.data.size();
  if (size < 8) {
    error = where() + "payload of " + std::to_string(size) + " bytes is shorter than a type fingerprint";
    return false;
  }
  std::uint64_t fingerprint = 0;
  for (std::size_t i = 0; i < 8; ++i) fingerprint = (fingerprint << 8) | event.data[i];
  const auto expected = static_cast<std::uint64_t>(Message::getHash());
  if (fingerprint != expected) {
    char text[96];
    std::snprintf(text, sizeof text, "type fingerprint 0x%016llx is not %s's 0x%016llx",
                  static_cast<unsigned long long>(fingerprint), Message::getTypeName(),
                  static_cast<unsigned long long>(expected));
    error = where() + text;
    return false;
  }
  // The reader caps every event at the file size, and LCM's sizes are int.
  if (size > static_cast<std::size_t>(INT32_MAX)) {
    error = where() + "payload of " + std::to_string(size) + " bytes is too large";
    return false;
  }
  // lcm-gen's decoders trust the lengths inside the payload (lcm_lengths.hpp).
  if (const std::string problem = payload_lengths_problem(out, event.data); !problem.empty()) {
    error = where() + problem;
    return false;
  }
  const int used = out.decode(event.data.data(), 0, static_cast<int>(size));
  if (used < 0) {
    error = where() + "payload of " + std::to_string(size) + " bytes does not decode as " + Message::getTypeName() +
            " (too short or malformed)";
    return false;
  }
  if (static_cast<std::size_t>(used) != size) {
    error = where() + std::to_string(size - static_cast<std::size_t>(used)) + " trailing bytes after " +
            Message::getTypeName() + " (" + std::to_string(used) + " bytes)";
    return false;
  }
  return true;
}

}  // namespace sculpt::logging
