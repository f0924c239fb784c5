#include "sculpt/logging/event_log_walk.hpp"

#include <limits>
#include <utility>
#include <vector>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_check.hpp"
#include "sculpt_lcm/log_check_t.hpp"

namespace sculpt::logging {
namespace {

// What the walk met, in file order: an event, or damage (held in order with the events).
struct Met {
  LogEvent event;
  bool damage = false;
  std::uint64_t offset = 0;  // damage's
  std::string what;          // damage's
};

// The walk of a checked log: what it meets is held until the check that covers it, then handed
// on in order, an event whose CRC-32 does not match its check as damage. An event no check
// covers (its check was damaged) goes on unchecked; so does the tail a crash left after the
// last check.
class CheckedWalk {
 public:
  CheckedWalk(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
              const std::function<void(std::uint64_t, const std::string&)>& on_damage)
      : path_(path), on_event_(on_event), on_damage_(on_damage) {}

  // Takes `event`'s buffers (swapped with a spent entry's, so that their capacity goes round).
  void hold(LogEvent& event) {
    Met& met = next_slot();
    std::swap(met.event, event);
    met.damage = false;
  }
  void hold_damage(std::uint64_t offset, const std::string& what) {
    Met& met = next_slot();
    met.damage = true;
    met.offset = offset;
    met.what = what;
  }

  // A SCULPT_CHECK event: everything held is handed on in order, each event it covers only if
  // it matches; a check that does not decode (or whose numbers are not a log's) is damage, and
  // its events wait for the next check, which hands them on unchecked.
  void check(const LogEvent& event) {
    sculpt_lcm::log_check_t check;
    std::string error;
    if (!decode(event, check, error)) {
      hold_damage(event.offset, path_ + ": byte offset " + std::to_string(event.offset) + ": " + error);
      return;
    }
    if (check.count < 0 || static_cast<std::size_t>(check.count) != check.crc.size() || check.first_event < 0 ||
        check.first_event > std::numeric_limits<std::int64_t>::max() - check.count) {
      hold_damage(event.offset, path_ + ": byte offset " + std::to_string(event.offset) +
                                    ": a check whose numbers are not a log's (first event " +
                                    std::to_string(check.first_event) + ", count " + std::to_string(check.count) + ")");
      return;
    }
    // Every event held came before this check, and the durable log writes a check after its
    // events: one outside the check's numbers is one whose own check was damaged, handed on
    // unchecked.
    const std::int64_t first = check.first_event, end = first + check.count;
    for (std::size_t k = 0; k < held_; ++k) {
      const Met& met = held_items_[k];
      if (met.damage) {
        on_damage_(met.offset, met.what);
        continue;
      }
      const LogEvent& e = met.event;
      if (e.number >= first && e.number < end) {
        const auto expected = static_cast<std::uint32_t>(check.crc[static_cast<std::size_t>(e.number - first)]);
        if (event_crc32(e.number, e.utime, e.channel, e.data.data(), e.data.size()) != expected) {
          ++failed_;
          on_damage_(e.offset, path_ + ": byte offset " + std::to_string(e.offset) + ": event " +
                                   std::to_string(e.number) + " on " + e.channel +
                                   " does not match its check (CRC-32 of the log's check at byte offset " +
                                   std::to_string(event.offset) + "): a byte in it changed");
          continue;
        }
      }
      on_event_(e);
    }
    held_ = 0;
  }

  // The end of the log: what no check followed (a crash's tail) goes on as it was read.
  void finish() {
    for (std::size_t k = 0; k < held_; ++k) {
      Met& met = held_items_[k];
      if (met.damage) {
        on_damage_(met.offset, met.what);
      } else {
        on_event_(met.event);
      }
    }
    held_ = 0;
  }

  std::uint64_t failed() const noexcept { return failed_; }

 private:
  Met& next_slot() {
    if (held_ == held_items_.size()) held_items_.emplace_back();
    return held_items_[held_++];
  }

  const std::string& path_;
  const std::function<void(const LogEvent&)>& on_event_;
  const std::function<void(std::uint64_t, const std::string&)>& on_damage_;
  std::vector<Met> held_items_;  // the first held_ are held; the rest keep their buffers
  std::size_t held_ = 0;
  std::uint64_t failed_ = 0;
};

}  // namespace

EventLogTotals for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
                              const std::function<void(std::uint64_t offset, const std::string& what)>& on_damage) {
  EventLogReader reader(path);
  CheckedWalk walk(path, on_event, on_damage);
  // Whether the log is checked is known at its second valid event: the durable log writes a
  // check right after its first. Until then the first is held.
  enum class Checked { kUnknown, kYes, kNo } checked = Checked::kUnknown;
  std::size_t valid = 0;
  LogEvent event;  // one buffer for the whole walk of an unchecked log
  for (;;) {
    const EventLogReader::Result result = reader.next(event);
    if (result == EventLogReader::Result::kEnd) break;
    if (result == EventLogReader::Result::kCorrupt) {
      if (checked == Checked::kNo) {
        on_damage(reader.error_offset(), reader.error());
      } else {
        walk.hold_damage(reader.error_offset(), reader.error());
      }
      continue;
    }
    const bool is_check = event.channel == kCheckChannel;
    if (checked == Checked::kUnknown && ++valid == 2) {
      checked = is_check ? Checked::kYes : Checked::kNo;
      if (checked == Checked::kNo) walk.finish();  // the first event, and damage before this one
    }
    if (checked == Checked::kNo) {
      if (!is_check) on_event(event);  // a check in a log read unchecked (its first was cut off)
    } else if (is_check) {
      walk.check(event);
    } else {
      walk.hold(event);
    }
  }
  walk.finish();
  return {reader.file_size(), reader.skipped_bytes(), reader.corrupt_events() + walk.failed(), walk.failed()};
}

}  // namespace sculpt::logging
