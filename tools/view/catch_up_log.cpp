#include "catch_up_log.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <system_error>
#include <utility>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_check.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "session_log.hpp"

namespace sculpt::view {

CatchUpLog::CatchUpLog(std::string path) : path_(std::move(path)) {}

void CatchUpLog::start_over() {
  resume_ = 0;
  held_.clear();
  forgotten_below_ = 0;
  newest_ = -1;
  checks_ = Checks::kUnknown;
  events_seen_ = 0;
  unchecked_.clear();
}

void CatchUpLog::trust(const logging::CollisionRecord& record) {
  newest_ = std::max(newest_, record.frame_id);
  if (record.frame_id >= forgotten_below_) held_.push_back(record);
}

void CatchUpLog::take(const logging::LogEvent& event) {
  ++events_seen_;
  const bool is_check = event.channel == logging::kCheckChannel;
  // The durable log writes its first check right after its first event: a log whose second
  // event is something else has no checks (lcm-logger's, or one from before checks) and is read
  // as it is. A whole read waits longer (its first check may be damaged), but a live viewer
  // cannot hold a foreign log's frames for 8,193 events.
  if (checks_ == Checks::kUnknown && events_seen_ >= 2 && !is_check) {
    checks_ = Checks::kNo;
    for (const Unchecked& u : unchecked_) trust(u.record);
    unchecked_.clear();
  }
  if (is_check) {
    take_check(event);
    return;
  }
  if (event.channel != logging::kCollisionChannel) return;
  logging::CollisionRecord record;
  if (!collision_from(event, record)) {
    ++damaged_;
  } else if (checks_ == Checks::kNo) {
    trust(record);
  } else {
    unchecked_.push_back(
        {record, event.number,
         logging::event_crc32(event.number, event.utime, event.channel, event.data.data(), event.data.size())});
  }
}

void CatchUpLog::take_check(const logging::LogEvent& event) {
  // A check this late in a log without them is another program's copy of one.
  if (checks_ == Checks::kNo && events_seen_ > logging::kEventsBeforeUnchecked) return;
  sculpt_lcm::log_check_t check;
  std::string error;
  if (!logging::read_check(event, check, error)) {
    ++damaged_;  // its collisions wait on, and the next check leaves them out
    return;
  }
  checks_ = Checks::kYes;
  std::size_t kept = 0;
  bool left_out = false;
  for (const Unchecked& u : unchecked_) {
    if (const std::optional<std::uint32_t> crc = logging::checked_crc(check, u.number)) {
      if (*crc == u.crc) {
        trust(u.record);
      } else {
        ++failed_checks_;
        ++damaged_;
      }
    } else if (u.number < check.first_event) {
      // Every event before a check is its own or an earlier check's: this one's was lost.
      ++left_out_;
      left_out = true;
    } else {
      unchecked_[kept++] = u;  // after this check: the next one's
    }
  }
  unchecked_.resize(kept);
  if (left_out) ++damaged_;
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
    take(event);
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
  result.damage = damaged_ - damage_answered_;
  damage_answered_ = damaged_;
  return result;
}

}  // namespace sculpt::view
