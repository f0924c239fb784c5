// Editing the edit history (rt/log_edit.hpp) against independent truth: a log cut anywhere
// keeps exactly its whole frames; dropping a stroke is the transfer of the log with that
// stroke's events filtered out here, by hand; and where the strokes' regions are disjoint it
// is the session recorded without the stroke.
#include "sculpt/rt/log_edit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "sculpt/deform/deformer.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/rt/collision_records.hpp"
#include "sculpt/rt/station.hpp"
#include "sculpt/rt/transfer.hpp"
#include "support/same_bytes.hpp"

namespace sculpt::rt {
namespace {

using deform::Vec3;
using logging::CollisionRecord;

constexpr FingerId kIndex{1, 1};
constexpr FingerId kThumb{1, 0};

// One finger's probe at frame `k` of a press that slides along the sphere at `azimuth`, or
// nothing when the finger is not scripted at that frame.
struct Script {
  FingerId finger;
  int first = 0, last = 0;  // frames it presses in
  double azimuth = 0.0;
};

deform::ProbeMotion probe_at(const Script& s, int k) {
  const auto at = [&](int j) {
    const double a = s.azimuth + 0.02 * (j - s.first);
    const double r = 1.015 - 0.012 * (j - s.first);  // from outside, deeper while it slides
    return Vec3{r * std::cos(a), r * std::sin(a), 0.0};
  };
  return {at(k - 1), at(k), at(k - 2)};
}

struct Session {
  std::vector<CollisionRecord> log;
  deform::PointModel model;
};

// A session of `frames` frames run through the live deformer: each frame the scripted fingers
// that are pressing are solved jointly, and its records are what the station would log.
Session record(const std::vector<Script>& scripts, int frames) {
  Session s{{}, deform::make_sphere()};
  deform::DeformSettings settings;
  settings.contact.bc_radius = 0.08;
  settings.region.kind = deform::RegionSettings::Kind::kRadius;
  settings.region.radius = 0.3;
  settings.max_probes = 2;  // as the station sizes it: one report slot per finger, so records name their finger
  deform::Deformer deformer(s.model, settings);
  std::int64_t id = 0;  // as the station counts: each applied (sub)frame its own id
  for (int k = 0; k < frames; ++k) {
    std::vector<deform::ProbeMotion> probes;
    std::vector<FingerId> fingers;
    for (const Script& script : scripts) {
      if (k < script.first || k > script.last) continue;
      probes.push_back(probe_at(script, k));
      fingers.push_back(script.finger);
    }
    if (probes.empty()) continue;
    deformer.deform(probes);
    const std::int64_t step = id;
    id += std::max<std::int64_t>(static_cast<std::int64_t>(deformer.frames().size()), 1);
    for (const deform::FrameReport& applied : deformer.frames()) {
      FrameRecord frame;
      frame.frame_id = step + (&applied - deformer.frames().data());
      frame.report = &applied;
      frame.settings = &deformer.settings();
      frame.fingers = fingers;
      frame.probes = probes;
      std::array<CollisionRecord, deform::kMaxSources> out;
      const std::size_t n = frame_collision_records(frame, out);
      s.log.insert(s.log.end(), out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n));
    }
  }
  return s;
}

deform::PointModel transferred(const std::vector<CollisionRecord>& log) {
  deform::PointModel m = deform::make_sphere();
  transfer(m, log);
  return m;
}

using test::same_bytes;

// Index and thumb press at the same time on opposite sides (their frames are solved jointly),
// then the index presses again alone.
const std::vector<Script> kTwoFingers = {{kIndex, 2, 9, 0.0}, {kThumb, 5, 12, 3.1}, {kIndex, 16, 22, 0.3}};

TEST(LogEdit, StrokesAreEachFingersRunsOfConsecutiveFrames) {
  const Session s = record(kTwoFingers, 24);
  ASSERT_FALSE(s.log.empty());
  // The truth from the log itself: each finger's collision frame ids, split at gaps.
  std::map<std::pair<int, int>, std::vector<std::int64_t>> frames;
  for (const CollisionRecord& r : s.log) frames[{r.hand, r.finger}].push_back(r.frame_id);
  std::size_t runs = 0;
  for (const auto& [finger, ids] : frames) {
    runs += 1;
    for (std::size_t i = 1; i < ids.size(); ++i) runs += ids[i] != ids[i - 1] + 1 ? 1 : 0;
  }
  const std::vector<Stroke> strokes = list_strokes(s.log);
  ASSERT_EQ(strokes.size(), runs);
  std::size_t events = 0;
  for (std::size_t i = 0; i < strokes.size(); ++i) {
    EXPECT_EQ(strokes[i].number, i + 1);
    EXPECT_LE(strokes[i].first_frame, strokes[i].last_frame);
    if (i > 0) {
      EXPECT_LE(strokes[i - 1].first_frame, strokes[i].first_frame);
    }
    events += strokes[i].events;
  }
  EXPECT_EQ(events, s.log.size());
}

TEST(LogEdit, DroppingAStrokeIsTheTransferOfTheLogWithoutItsEvents) {
  const Session s = record(kTwoFingers, 24);
  for (const Stroke& stroke : list_strokes(s.log)) {
    // Filtered here: every event of that finger in the stroke's frames goes, and each frame's
    // size is recounted from what is left.
    std::vector<CollisionRecord> filtered;
    for (const CollisionRecord& r : s.log) {
      const bool in_stroke = r.hand == stroke.hand && r.finger == stroke.finger && r.frame_id >= stroke.first_frame &&
                             r.frame_id <= stroke.last_frame;
      if (!in_stroke) filtered.push_back(r);
    }
    std::map<std::int64_t, std::uint8_t> sizes;
    for (const CollisionRecord& r : filtered) ++sizes[r.frame_id];
    for (CollisionRecord& r : filtered) r.frame_size = sizes[r.frame_id];
    ASSERT_EQ(filtered.size(), s.log.size() - stroke.events);

    const deform::PointModel edited = transferred(drop_stroke(s.log, stroke));
    const deform::PointModel truth = transferred(filtered);
    EXPECT_TRUE(same_bytes(edited.x, truth.x) && same_bytes(edited.y, truth.y) && same_bytes(edited.z, truth.z))
        << "stroke " << stroke.number;
  }
}

TEST(LogEdit, DroppingAStrokeWithADisjointRegionIsTheSessionWithoutIt) {
  // The thumb presses between the index's two strokes, on the far side: regions of radius 0.3
  // around contacts about 2 apart never share a point, and the frames never share a solve.
  const std::vector<Script> three = {{kIndex, 2, 8, 0.0}, {kThumb, 10, 16, 3.1}, {kIndex, 18, 24, 0.2}};
  const Session with = record(three, 26);
  const Session without = record({three[0], three[2]}, 26);
  // The thumb's press may break into several strokes (frames where it sits in its own dent
  // without colliding): every one of them goes.
  std::vector<CollisionRecord> log = with.log;
  std::size_t thumb_strokes = 0;
  for (const Stroke& s : list_strokes(with.log)) {
    if (s.finger != kThumb.finger) continue;
    log = drop_stroke(log, s);
    ++thumb_strokes;
  }
  ASSERT_GT(thumb_strokes, 0u);
  const deform::PointModel edited = transferred(log);
  ASSERT_EQ(edited.size(), without.model.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < edited.size(); ++i) {
    worst = std::max(worst, norm(edited.position(i) - without.model.position(i)));
  }
  EXPECT_LE(worst, 1e-6);  // float precision of unit-sphere coordinates
  // And the thumb did sculpt: the edit is not the whole session.
  double moved = 0.0;
  for (std::size_t i = 0; i < edited.size(); ++i) {
    moved = std::max(moved, norm(edited.position(i) - with.model.position(i)));
  }
  EXPECT_GT(moved, 1e-3);
}

TEST(LogEdit, ACutKeepsExactlyTheWholeFramesBeforeIt) {
  const Session s = record(kTwoFingers, 24);
  for (std::size_t cut = 0; cut <= s.log.size(); ++cut) {
    const std::span<const CollisionRecord> prefix(s.log.data(), cut);
    // Truth: the frames whose every event (frame_size of them) lies before the cut.
    std::map<std::int64_t, std::size_t> count;
    for (const CollisionRecord& r : prefix) ++count[r.frame_id];
    std::size_t whole_events = 0;
    std::int64_t last = -1;
    for (const CollisionRecord& r : prefix) {
      if (count[r.frame_id] == r.frame_size) {
        ++whole_events;
        last = r.frame_id;
      }
    }
    const WholeFrames w = whole_frames(prefix);
    EXPECT_EQ(w.events, whole_events) << "cut after " << cut << " events";
    EXPECT_EQ(w.last_frame, last);
    EXPECT_EQ(w.cut_at_end, whole_events < cut);
    EXPECT_EQ(until_frame(s.log, last).size(), whole_events);
  }
}

TEST(LogEdit, AFrameShortOfEventsInsideTheLogIsDamageNotACut) {
  Session s = record(kTwoFingers, 24);
  std::size_t joint = 0;  // an event of a two-finger frame
  while (joint < s.log.size() && s.log[joint].frame_size < 2) ++joint;
  ASSERT_LT(joint, s.log.size());
  std::vector<CollisionRecord> damaged = s.log;
  damaged.erase(damaged.begin() + static_cast<std::ptrdiff_t>(joint));
  const WholeFrames w = whole_frames(damaged);
  EXPECT_FALSE(w.cut_at_end);
  EXPECT_EQ(w.events, joint);
  const std::vector<CollisionRecord> kept = drop_incomplete_frames(damaged);
  EXPECT_EQ(kept.size(), damaged.size() - 1);  // the joint frame's remaining event goes
}

}  // namespace
}  // namespace sculpt::rt
