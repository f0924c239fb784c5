#include "sculpt/logging/event_log_walk.hpp"

#include <algorithm>
#include <cstddef>
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
  bool cut = false;          // damage that is bytes running out at the end (EventLogReader)
  std::uint64_t offset = 0;  // damage's
  std::string what;          // damage's
};

// The walk of a checked log: what it meets is held until the next check, then handed on in
// order, an event whose CRC-32 does not match its check as damage. Events that check does not
// cover (their own check was damaged, renamed or swallowed) are damage too, one report for the
// run of them: a length changed in one event can swallow the check after it, and the event
// with it. The tail a crash left after the last check goes on unchecked, as before checks.
class CheckedWalk {
 public:
  CheckedWalk(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
              const std::function<void(std::uint64_t, const std::string&)>& on_damage)
      : path_(path), on_event_(on_event), on_damage_(on_damage) {}

  std::size_t held() const noexcept { return held_; }

  // Takes `event`'s buffers (swapped with a spent entry's, so that their capacity goes round).
  void hold(LogEvent& event) {
    Met& met = next_slot();
    std::swap(met.event, event);
    met.damage = false;
  }
  void hold_damage(std::uint64_t offset, const std::string& what, bool cut = false) {
    Met& met = next_slot();
    met.damage = true;
    met.cut = cut;
    met.offset = offset;
    met.what = what;
  }

  // A SCULPT_CHECK event: everything held is handed on in order, each event it covers only if
  // it matches; a check that does not decode (or whose numbers are not a log's) is damage, and
  // so are its events at the next check.
  void check(const LogEvent& event) {
    sculpt_lcm::log_check_t check;
    std::string error;
    if (!read_check(event, check, error)) {
      ++bad_checks_;
      hold_damage(event.offset, path_ + ": " + error);
      return;
    }
    const auto covered = [&](const Met& met) { return met.damage || checked_crc(check, met.event.number); };
    for (std::size_t k = 0; k < held_; ++k) {
      const Met& met = held_items_[k];
      if (met.damage) {
        on_damage_(met.offset, met.what);
        continue;
      }
      const LogEvent& e = met.event;
      if (!covered(met)) {
        // Every event before a check is its own or an earlier check's: this one's check is gone
        // (damaged, renamed, or swallowed by a damaged length), and its bytes cannot be trusted.
        if (k == 0 || covered(held_items_[k - 1])) {
          report_uncovered(
              k, covered,
              "their own was damaged: the check at byte offset " + std::to_string(event.offset) + " is the next one's");
        }
        continue;
      }
      if (event_crc32(e.number, e.utime, e.channel, e.data.data(), e.data.size()) != *checked_crc(check, e.number)) {
        ++failed_;
        on_damage_(e.offset, where(e.offset) + "event " + std::to_string(e.number) + " on " + e.channel +
                                 " does not match its check (CRC-32 of the log's check at byte offset " +
                                 std::to_string(event.offset) + "): a byte in it changed");
        continue;
      }
      on_event_(e);
    }
    held_ = 0;
  }

  // The end of a log without checks, or of the events it is known by: what is held goes on as
  // it was read.
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

  // The end of a checked log. Its tail after the last check goes on unchecked when it is what a
  // crash leaves (whole events, perhaps cut short at the end); damage of another kind among
  // them may have swallowed their check (a length changed in the last event reaches into it),
  // so then the tail's events are left out, one report for them.
  void finish_checked(std::uint64_t file_size) {
    const bool crash_tail = std::none_of(held_items_.begin(), held_items_.begin() + static_cast<std::ptrdiff_t>(held_),
                                         [](const Met& met) { return met.damage && !met.cut; });
    if (crash_tail) {
      finish();
      return;
    }
    const auto covered = [](const Met& met) { return met.damage; };
    for (std::size_t k = 0; k < held_; ++k) {
      const Met& met = held_items_[k];
      if (met.damage) {
        on_damage_(met.offset, met.what);
      } else if (k == 0 || covered(held_items_[k - 1])) {
        report_uncovered(k, covered,
                         "damage follows them to the end of the log, at " + std::to_string(file_size) +
                             " bytes, which may have swallowed their check");
      }
    }
    held_ = 0;
  }

  std::uint64_t failed() const noexcept { return failed_; }
  std::uint64_t left_out() const noexcept { return left_out_; }
  // Places reported as damage by the walk itself (the reader counts its own).
  std::uint64_t damage_found() const noexcept { return failed_ + runs_left_out_ + bad_checks_; }

 private:
  std::string where(std::uint64_t offset) const { return path_ + ": byte offset " + std::to_string(offset) + ": "; }

  // One damage report for the run of held events from `k` that no check covers (left out),
  // saying `why`.
  template <typename Covered>
  void report_uncovered(std::size_t k, const Covered& covered, const std::string& why) {
    std::size_t count = 0;
    std::uint64_t last = held_items_[k].event.offset;
    for (std::size_t j = k; j < held_ && !covered(held_items_[j]); ++j, ++count) last = held_items_[j].event.offset;
    left_out_ += count;
    ++runs_left_out_;
    on_damage_(held_items_[k].event.offset, where(held_items_[k].event.offset) + std::to_string(count) +
                                                " events, to the one at byte offset " + std::to_string(last) +
                                                ", are covered by no check (" + why + "): left out");
  }

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
  std::uint64_t left_out_ = 0, runs_left_out_ = 0, bad_checks_ = 0;
};

}  // namespace

EventLogTotals for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
                              const std::function<void(std::uint64_t offset, const std::string& what)>& on_damage) {
  EventLogReader reader(path);
  CheckedWalk walk(path, on_event, on_damage);
  // A log is checked from its first check on; one with no check among its first
  // kEventsBeforeUnchecked events is read as it always was. Until one or the other is known,
  // what the walk meets is held.
  enum class Checked { kUnknown, kYes, kNo } checked = Checked::kUnknown;
  LogEvent event;  // one buffer for the whole walk of an unchecked log
  for (;;) {
    const EventLogReader::Result result = reader.next(event);
    if (result == EventLogReader::Result::kEnd) break;
    if (result == EventLogReader::Result::kCorrupt) {
      if (checked == Checked::kNo) {
        on_damage(reader.error_offset(), reader.error());
      } else {
        walk.hold_damage(reader.error_offset(), reader.error(), reader.error_is_cut());
      }
      continue;
    }
    const bool is_check = event.channel == kCheckChannel;
    if (checked == Checked::kNo) {
      if (!is_check) on_event(event);  // a check this late is another program's copy of one
      continue;
    }
    if (is_check) {
      checked = Checked::kYes;
      walk.check(event);
      continue;
    }
    walk.hold(event);
    if (checked == Checked::kUnknown && walk.held() >= kEventsBeforeUnchecked) {
      checked = Checked::kNo;
      walk.finish();
    }
  }
  if (checked == Checked::kYes) {
    walk.finish_checked(reader.file_size());
  } else {
    walk.finish();
  }
  return {reader.file_size(), reader.skipped_bytes(), reader.corrupt_events() + walk.damage_found(), walk.failed(),
          walk.left_out()};
}

}  // namespace sculpt::logging
