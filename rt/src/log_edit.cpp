#include "sculpt/rt/log_edit.hpp"

#include <map>
#include <utility>

#include "sculpt/logging/frame_runs.hpp"

namespace sculpt::rt {
namespace {

using logging::CollisionRecord;
using logging::frame_run_end;
using logging::whole_frame;

bool stroke_event(const CollisionRecord& r, const Stroke& s) noexcept {
  return r.hand == s.hand && r.finger == s.finger && r.frame_id >= s.first_frame && r.frame_id <= s.last_frame;
}

}  // namespace

WholeFrames whole_frames(std::span<const CollisionRecord> events) noexcept {
  WholeFrames w;
  std::size_t begin = 0;
  while (begin < events.size()) {
    const std::size_t end = frame_run_end(events, begin);
    const auto run = events.subspan(begin, end - begin);
    if (!whole_frame(run)) {
      // Only a final frame short of events is what a cut leaves; a frame with too many events,
      // or one followed by others, is damage.
      w.cut_at_end = end == events.size() && run.size() < run.front().frame_size;
      return w;
    }
    w.events = end;
    ++w.frames;
    w.last_frame = run.front().frame_id;
    begin = end;
  }
  return w;
}

std::vector<CollisionRecord> drop_incomplete_frames(std::span<const CollisionRecord> events) {
  std::vector<CollisionRecord> out;
  out.reserve(events.size());
  for (std::size_t begin = 0; begin < events.size();) {
    const std::size_t end = frame_run_end(events, begin);
    const auto run = events.subspan(begin, end - begin);
    if (whole_frame(run)) out.insert(out.end(), run.begin(), run.end());
    begin = end;
  }
  return out;
}

std::vector<CollisionRecord> until_frame(std::span<const CollisionRecord> events, std::int64_t last_frame) {
  std::vector<CollisionRecord> out;
  for (const CollisionRecord& r : events) {
    if (r.frame_id <= last_frame) out.push_back(r);
  }
  return out;
}

std::vector<Stroke> list_strokes(std::span<const CollisionRecord> events) {
  std::vector<Stroke> strokes;
  std::map<std::pair<std::uint8_t, std::uint8_t>, std::size_t> open;  // finger -> its last stroke
  for (const CollisionRecord& r : events) {
    const auto finger = std::make_pair(r.hand, r.finger);
    const auto it = open.find(finger);
    if (it != open.end() && r.frame_id == strokes[it->second].last_frame + 1) {
      Stroke& s = strokes[it->second];
      s.last_frame = r.frame_id;
      ++s.events;
      continue;
    }
    Stroke s;
    s.number = strokes.size() + 1;
    s.hand = r.hand;
    s.finger = r.finger;
    s.first_frame = s.last_frame = r.frame_id;
    s.events = 1;
    open[finger] = strokes.size();
    strokes.push_back(s);
  }
  return strokes;
}

std::vector<CollisionRecord> drop_stroke(std::span<const CollisionRecord> events, const Stroke& stroke) {
  std::vector<CollisionRecord> out;
  out.reserve(events.size());
  for (std::size_t begin = 0; begin < events.size();) {
    const std::size_t end = frame_run_end(events, begin);
    std::size_t dropped = 0;
    for (std::size_t k = begin; k < end; ++k) dropped += stroke_event(events[k], stroke) ? 1 : 0;
    for (std::size_t k = begin; k < end; ++k) {
      if (stroke_event(events[k], stroke)) continue;
      CollisionRecord r = events[k];
      // The frame is smaller by what left it, not recounted: a frame that was already short
      // (damage) must still read as short.
      r.frame_size = static_cast<std::uint8_t>(r.frame_size >= dropped ? r.frame_size - dropped : 0);
      out.push_back(r);
    }
    begin = end;
  }
  return out;
}

}  // namespace sculpt::rt
