// The viewer's catch-up log read as the station writes it: a log written by LCM's own writer is
// copied into place a piece at a time, cut anywhere (inside headers, inside payloads), and
// after every piece the incremental reader must answer what a fresh whole-file read of the
// same bytes answers, while reading each byte about once.
#include "catch_up_log.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "session_log.hpp"
#include "support/lcm_round_trip.hpp"
#include "support/scratch_dir.hpp"

namespace sculpt::view {
namespace {

using Bytes = std::vector<std::uint8_t>;
constexpr std::int64_t kLastFrame = std::numeric_limits<std::int64_t>::max();

std::string temp_path(const std::string& name) {
  static const test::ScratchDir kScratch("sculpt_catch_up_test_");
  return (kScratch.path() / name).string();
}

// A session's shape: ticks at 1 kHz, and every third tick a frame of one or two events.
std::vector<std::pair<std::string, Bytes>> session_events(int ticks) {
  std::vector<std::pair<std::string, Bytes>> events;
  std::int64_t frame = 0;
  for (int t = 0; t < ticks; ++t) {
    const int size = t % 3 != 0 ? 0 : (t % 2 == 0 ? 2 : 1);
    for (int k = 0; k < size; ++k) {
      logging::CollisionRecord r;
      r.tick = t;
      r.frame_id = frame;
      r.frame_size = static_cast<std::uint8_t>(size);
      r.contact_index = k;
      r.force = {0.001 * t, -0.002, 0.003 * k};
      sculpt_lcm::collision_event_t message{};
      logging::to_lcm(r, message);
      events.emplace_back(logging::kCollisionChannel, test::lcm_encode(message));
    }
    frame += size > 0 ? 1 : 0;
    logging::TickRecord tick;
    tick.tick = t;
    tick.collisions = static_cast<std::int16_t>(size);
    sculpt_lcm::tick_stats_t message{};
    logging::to_lcm(tick, message);
    events.emplace_back(logging::kTickChannel, test::lcm_encode(message));
  }
  return events;
}

Bytes written_by_lcm(const std::vector<std::pair<std::string, Bytes>>& events) {
  const std::string path = temp_path("source.lcmlog");
  {
    lcm::LogFile log(path, "w");
    std::int64_t i = 0;
    for (const auto& [channel, payload] : events) {
      lcm::LogEvent event;
      event.eventnum = i;
      event.timestamp = 1000 + i++;
      event.channel = channel;
      event.datalen = static_cast<std::int32_t>(payload.size());
      event.data = const_cast<std::uint8_t*>(payload.data());
      log.writeEvent(&event);
    }
  }
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void save(const std::string& path, const Bytes& bytes, std::size_t count) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(count));
}

// What reading the whole file afresh answers: the old catch-up, kept here as the truth.
CatchUpResult whole_file(const std::string& path, std::int64_t first, std::int64_t last) {
  CatchUpResult result;
  for (const logging::CollisionRecord& r : read_session_log(path).collisions) {
    if (r.frame_id >= first && r.frame_id <= last) result.events.push_back(r);
    result.reached = result.reached || r.frame_id > last;
  }
  return result;
}

void expect_same(const CatchUpResult& got, const CatchUpResult& truth, const std::string& where) {
  EXPECT_EQ(got.reached, truth.reached) << where;
  ASSERT_EQ(got.events.size(), truth.events.size()) << where;
  for (std::size_t k = 0; k < got.events.size(); ++k) {
    EXPECT_EQ(got.events[k].frame_id, truth.events[k].frame_id) << where;
    EXPECT_EQ(got.events[k].tick, truth.events[k].tick) << where;
    EXPECT_EQ(got.events[k].contact_index, truth.events[k].contact_index) << where;
  }
}

TEST(CatchUpLog, AGrowingLogCutAnywhereAnswersAsAWholeReadAndIsReadAboutOnce) {
  const Bytes bytes = written_by_lcm(session_events(1000));
  const std::string path = temp_path("live.lcmlog");
  save(path, bytes, 0);
  CatchUpLog log(path);
  // Cut points spread over the file at odd strides, so that they fall in headers, channel
  // names and payloads alike; the follower's next frame advances as a viewer's would.
  std::uint64_t rereads = 0, pieces = 0;
  std::int64_t next = 0;
  for (std::size_t cut = 0; cut < bytes.size(); cut = std::min(bytes.size(), cut + 2999 + cut % 89)) {
    save(path, bytes, cut);
    const std::int64_t last = next + 3 + static_cast<std::int64_t>(pieces % 5);
    expect_same(log.events(next, last), whole_file(path, next, last), "cut at byte " + std::to_string(cut));
    if (pieces % 4 == 3) {  // sometimes the gap is "everything the log has"
      expect_same(log.events(next, kLastFrame), whole_file(path, next, kLastFrame), "all, cut " + std::to_string(cut));
    }
    rereads += cut;
    ++pieces;
    next += 2;
  }
  save(path, bytes, bytes.size());
  expect_same(log.events(next, kLastFrame), whole_file(path, next, kLastFrame), "the whole log");
  EXPECT_EQ(log.damaged(), 0u) << "an unflushed tail is not damage";
  std::printf("[ view ] %zu bytes in %llu pieces: read %llu bytes incrementally, %llu rereading\n", bytes.size(),
              static_cast<unsigned long long>(pieces), static_cast<unsigned long long>(log.bytes_read()),
              static_cast<unsigned long long>(rereads));
  // Each call reads what was appended and the cut event again: at most a header, a channel
  // name and a collision payload more than the file.
  EXPECT_LE(log.bytes_read(), bytes.size() + 2 * pieces * 256);
  EXPECT_LT(log.bytes_read(), rereads / 20);
}

TEST(CatchUpLog, DamageInsideIsCountedAndPassedAndANewSessionStartsOver) {
  const std::vector<std::pair<std::string, Bytes>> events = session_events(300);
  Bytes bytes = written_by_lcm(events);
  const std::string path = temp_path("damaged.lcmlog");
  save(path, bytes, bytes.size() / 2);
  CatchUpLog log(path);
  const CatchUpResult half = log.events(0, kLastFrame);
  ASSERT_FALSE(half.events.empty());
  // A flipped sync word in the half already read changes nothing read; one in the half still
  // to come is damage once an event follows it, and the events around it are found.
  Bytes damaged = bytes;
  const std::size_t flip = bytes.size() * 3 / 4;
  const std::uint8_t sync[] = {0xED, 0xA1, 0xDA, 0x01};
  const auto at = static_cast<std::size_t>(
      std::search(damaged.begin() + static_cast<long>(flip), damaged.end(), std::begin(sync), std::end(sync)) -
      damaged.begin());
  ASSERT_LT(at, damaged.size());
  damaged[at] ^= 0xFF;
  save(path, damaged, damaged.size());
  const std::int64_t next = half.events.back().frame_id;
  expect_same(log.events(next, kLastFrame), whole_file(path, next, kLastFrame), "past the damage");
  EXPECT_EQ(log.damaged(), 1u);

  // The station started a new session under the same name: a shorter log, read from its start
  // (the follower, which knows nothing of it, asks from the same frame on).
  const Bytes fresh = written_by_lcm(session_events(240));
  ASSERT_LT(fresh.size(), damaged.size());
  save(path, fresh, fresh.size());
  const CatchUpResult again = log.events(next, kLastFrame);
  EXPECT_FALSE(again.events.empty());
  expect_same(again, whole_file(path, next, kLastFrame), "a new session");
  // A follower that asks again from an earlier frame is answered from the start too.
  save(path, bytes, bytes.size());
  expect_same(log.events(5, 9), whole_file(path, 5, 9), "forward");
  expect_same(log.events(1, 4), whole_file(path, 1, 4), "backward");
}

}  // namespace
}  // namespace sculpt::view
