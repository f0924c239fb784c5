#include "sculpt/logging/frame_runs.hpp"

namespace sculpt::logging {

std::size_t frame_run_end(std::span<const CollisionRecord> events, std::size_t begin) noexcept {
  std::size_t end = begin + 1;
  while (end < events.size() && events[end].frame_id == events[begin].frame_id) ++end;
  return end;
}

bool whole_frame(std::span<const CollisionRecord> run) noexcept {
  for (const CollisionRecord& r : run) {
    if (r.frame_size != run.size()) return false;
  }
  return true;
}

}  // namespace sculpt::logging
