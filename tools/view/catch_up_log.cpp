#include "catch_up_log.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <system_error>
#include <utility>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "session_log.hpp"

namespace sculpt::view {

CatchUpLog::CatchUpLog(std::string path) : path_(std::move(path)) {}

void CatchUpLog::start_over() {
  resume_ = 0;
  held_.clear();
  forgotten_below_ = 0;
  newest_ = -1;
}

void CatchUpLog::read_appended() {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path_, error);
  if (!error && size < resume_) start_over();  // replaced by a shorter file: a new session
  logging::EventLogReader reader(path_, resume_);
  const std::uint64_t from = resume_;
  // Damage is known for damage only once a whole event follows it; until then it may be the
  // tail the station has not flushed yet, and the next call reads it again.
  std::optional<std::uint64_t> unsettled;
  logging::LogEvent event;
  for (;;) {
    const logging::EventLogReader::Result r = reader.next(event);
    if (r == logging::EventLogReader::Result::kEnd) break;
    if (r == logging::EventLogReader::Result::kCorrupt) {
      if (!unsettled) unsettled = reader.error_offset();
      continue;
    }
    if (unsettled) ++damaged_;
    unsettled.reset();
    resume_ = logging::end_of(event);
    if (event.channel != logging::kCollisionChannel) continue;
    logging::CollisionRecord record;
    if (!collision_from(event, record)) {
      ++damaged_;
      continue;
    }
    newest_ = std::max(newest_, record.frame_id);
    if (record.frame_id >= forgotten_below_) held_.push_back(record);
  }
  if (!unsettled) resume_ = reader.file_size();
  bytes_read_ += reader.file_size() - from;
}

CatchUpResult CatchUpLog::events(std::int64_t first, std::int64_t last) {
  if (first < forgotten_below_) start_over();
  read_appended();
  forgotten_below_ = first;
  std::erase_if(held_, [&](const logging::CollisionRecord& r) { return r.frame_id < first; });
  CatchUpResult result;
  for (const logging::CollisionRecord& r : held_) {
    if (r.frame_id <= last) result.events.push_back(r);
  }
  result.reached = newest_ > last;
  return result;
}

}  // namespace sculpt::view
