#include "sculpt/logging/event_log_walk.hpp"

namespace sculpt::logging {

EventLogTotals for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& on_event,
                              const std::function<void(std::uint64_t offset, const std::string& what)>& on_damage) {
  EventLogReader reader(path);
  LogEvent event;  // one buffer for the whole walk: its data vector keeps its capacity
  for (;;) {
    const EventLogReader::Result result = reader.next(event);
    if (result == EventLogReader::Result::kEnd) break;
    if (result == EventLogReader::Result::kCorrupt) {
      on_damage(reader.error_offset(), reader.error());
      continue;
    }
    on_event(event);
  }
  return {reader.file_size(), reader.skipped_bytes(), reader.corrupt_events()};
}

}  // namespace sculpt::logging
