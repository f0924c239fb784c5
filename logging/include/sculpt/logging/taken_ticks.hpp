#pragma once
// Which of the live loop's ticks took each glove sample of a station's log, read from the log's
// order. The loop takes a tick's samples first and logs them before anything else of that tick
// (its fingertips, collisions, haptic commands and tick record, all on channels of their own),
// so the samples between two of those events were taken by one tick. A re-run needs that
// grouping: the loop keeps only a hand's newest sample of those one tick takes.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace sculpt::logging {

class TakenTicks {
 public:
  /// A glove sample, the next in the log.
  void sample();
  /// Any other event: one of the loop's own channels ends the run of samples before it.
  void event(std::string_view channel);
  /// Damage in the log: whatever was lost, the samples on either side are not joined.
  void damage();
  /// Per sample, its tick numbered from 0 in the log's order (rt::SampleLog::taken); -1 for the
  /// samples after the last event that ends a run (a crash's tail: their tick is not known).
  std::vector<std::int64_t> finish() const;

 private:
  void end_run();

  std::vector<std::int64_t> taken_;
  std::size_t ended_ = 0;  // samples whose run has ended
  std::int64_t next_tick_ = 0;
};

}  // namespace sculpt::logging
