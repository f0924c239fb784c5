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
#include "sculpt/logging/event_check.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/log_check_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "session_log.hpp"
#include "support/lcm_round_trip.hpp"
#include "support/scratch_dir.hpp"

namespace sculpt::view {
namespace {

using Bytes = std::vector<std::uint8_t>;
constexpr std::int64_t kLastFrame = std::numeric_limits<std::int64_t>::max();

std::string catch_up_log_path(const std::string& name) {
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
  const std::string path = catch_up_log_path("source.lcmlog");
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

// The events with checks among them, as the durable log writes them: one after the first event
// and one after every `every` events more, each with the CRC-32 of the events since the last,
// numbered and stamped as written_by_lcm() numbers and stamps them; and a last one at the end,
// as the durable log's close writes.
std::vector<std::pair<std::string, Bytes>> with_checks(const std::vector<std::pair<std::string, Bytes>>& events,
                                                       std::size_t every) {
  std::vector<std::pair<std::string, Bytes>> out;
  sculpt_lcm::log_check_t check{};
  for (const auto& [channel, payload] : events) {
    const auto number = static_cast<std::int64_t>(out.size());
    if (check.count == 0) check.first_event = number;
    check.crc.push_back(static_cast<std::int32_t>(
        logging::event_crc32(number, 1000 + number, channel, payload.data(), payload.size())));
    ++check.count;
    out.emplace_back(channel, payload);
    if (number == 0 || check.crc.size() == every) {
      out.emplace_back(logging::kCheckChannel, test::lcm_encode(check));
      check.crc.clear();
      check.count = 0;
    }
  }
  if (check.count > 0) out.emplace_back(logging::kCheckChannel, test::lcm_encode(check));
  return out;
}

// Where each event of written_by_lcm(events) begins, and the file's size after it.
std::vector<std::size_t> event_offsets(const std::vector<std::pair<std::string, Bytes>>& events) {
  std::vector<std::size_t> offsets{0};
  for (const auto& [channel, payload] : events) {
    offsets.push_back(offsets.back() + logging::kLogHeaderSize + channel.size() + payload.size());
  }
  return offsets;
}

void save(const std::string& path, const Bytes& bytes, std::size_t count) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(count));
}

// The first half of the log in place at `path`, read as a viewer's first catch-up reads it.
CatchUpResult first_half(const Bytes& bytes, const std::string& path, CatchUpLog& log) {
  save(path, bytes, bytes.size() / 2);
  return log.events(0, kLastFrame);
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
  const std::string path = catch_up_log_path("live.lcmlog");
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
  const std::string path = catch_up_log_path("damaged.lcmlog");
  CatchUpLog log(path);
  const CatchUpResult half = first_half(bytes, path, log);
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

// A checked log is answered only as far as its checks reach: cut anywhere as it grows, the
// reader answers what a whole read of the file up to its last check answers (the whole read
// itself would hand on the unchecked tail, as a crash's).
TEST(CatchUpLog, AGrowingCheckedLogIsAnsweredAsFarAsItsLastCheck) {
  const auto events = with_checks(session_events(1000), 40);
  const std::vector<std::size_t> offsets = event_offsets(events);
  const Bytes bytes = written_by_lcm(events);
  ASSERT_EQ(offsets.back(), bytes.size());
  const std::string path = catch_up_log_path("checked.lcmlog"), checked = catch_up_log_path("checked_part.lcmlog");
  save(path, bytes, 0);
  CatchUpLog log(path);
  std::int64_t next = 0;
  std::size_t pieces = 0, answered = 0;
  for (std::size_t cut = 0; cut < bytes.size(); cut = std::min(bytes.size(), cut + 2999 + cut % 89)) {
    save(path, bytes, cut);
    std::size_t checked_to = 0;
    for (std::size_t k = 0; k < events.size() && offsets[k + 1] <= cut; ++k) {
      if (events[k].first == logging::kCheckChannel) checked_to = offsets[k + 1];
    }
    save(checked, bytes, checked_to);
    const std::int64_t last = next + 3 + static_cast<std::int64_t>(pieces % 5);
    const CatchUpResult got = log.events(next, last);
    expect_same(got, whole_file(checked, next, last), "cut at byte " + std::to_string(cut));
    answered += got.events.size();
    EXPECT_EQ(got.damage, 0u);
    ++pieces;
    next += 2;
  }
  save(path, bytes, bytes.size());
  expect_same(log.events(next, kLastFrame), whole_file(path, next, kLastFrame), "the whole log");
  EXPECT_GT(answered, 100u);
  EXPECT_EQ(log.damaged(), 0u);
  EXPECT_EQ(log.failed_checks(), 0u);
}

// The collision events of a checked log at or after byte `from`: their indices in `events`.
std::vector<std::size_t> collisions_after(const std::vector<std::pair<std::string, Bytes>>& events,
                                          const std::vector<std::size_t>& offsets, std::size_t from) {
  std::vector<std::size_t> found;
  for (std::size_t k = 0; k < events.size(); ++k) {
    if (offsets[k] >= from && events[k].first == logging::kCollisionChannel) found.push_back(k);
  }
  return found;
}

TEST(CatchUpLog, ACollisionThatDoesNotMatchItsCheckIsNeverAnswered) {
  const auto events = with_checks(session_events(300), 16);
  const std::vector<std::size_t> offsets = event_offsets(events);
  Bytes bytes = written_by_lcm(events);
  const std::string path = catch_up_log_path("flipped.lcmlog");
  CatchUpLog log(path);
  const CatchUpResult half = first_half(bytes, path, log);
  ASSERT_FALSE(half.events.empty());
  // The last byte of a collision's payload is its force's lowest mantissa byte: the event still
  // decodes, to a force a hair off, and only its check tells.
  const std::vector<std::size_t> later = collisions_after(events, offsets, bytes.size() * 3 / 4);
  ASSERT_FALSE(later.empty());
  const std::size_t k = later.front();
  bytes[offsets[k + 1] - 1] ^= 0x01;
  save(path, bytes, bytes.size());
  logging::CollisionRecord flipped;
  {
    const std::string alone = catch_up_log_path("flipped_event.lcmlog");
    save(alone, Bytes(bytes.begin() + static_cast<long>(offsets[k]), bytes.begin() + static_cast<long>(offsets[k + 1])),
         offsets[k + 1] - offsets[k]);
    const auto read = read_session_log(alone);
    ASSERT_EQ(read.collisions.size(), 1u) << "the flipped collision decodes on its own";
    flipped = read.collisions.front();
  }
  const std::int64_t next = half.events.back().frame_id;
  const CatchUpResult got = log.events(next, kLastFrame);
  expect_same(got, whole_file(path, next, kLastFrame), "past the flip");
  EXPECT_EQ(got.damage, 1u);
  EXPECT_EQ(log.damaged(), 1u);
  EXPECT_EQ(log.failed_checks(), 1u);
  EXPECT_TRUE(std::none_of(got.events.begin(), got.events.end(),
                           [&](const logging::CollisionRecord& r) {
                             return r.frame_id == flipped.frame_id && r.contact_index == flipped.contact_index;
                           }))
      << "frame " << flipped.frame_id;
  EXPECT_EQ(log.events(next, kLastFrame).damage, 0u) << "damage is answered once";
}

TEST(CatchUpLog, CollisionsWhoseCheckWasLostAreLeftOut) {
  const auto events = with_checks(session_events(300), 16);
  const std::vector<std::size_t> offsets = event_offsets(events);
  Bytes bytes = written_by_lcm(events);
  // A check in the log's second half, renamed: to a reader it is an event of another channel,
  // and the collisions it checked are covered by no check.
  std::size_t renamed = 0;
  std::size_t collisions = 0;
  for (std::size_t k = events.size() / 2; k < events.size(); ++k) {
    if (events[k].first == logging::kCheckChannel) {
      renamed = k;
      break;
    }
  }
  ASSERT_GT(renamed, 0u);
  for (std::size_t k = renamed; k-- > 0 && events[k].first != logging::kCheckChannel;) {
    collisions += events[k].first == logging::kCollisionChannel ? 1 : 0;
  }
  ASSERT_GT(collisions, 0u);
  bytes[offsets[renamed] + logging::kLogHeaderSize] ^= 0x20;  // SCULPT_CHECK -> sCULPT_CHECK
  const std::string path = catch_up_log_path("renamed.lcmlog");
  save(path, bytes, bytes.size());
  CatchUpLog log(path);
  const CatchUpResult got = log.events(0, kLastFrame);
  expect_same(got, whole_file(path, 0, kLastFrame), "a check renamed");
  EXPECT_EQ(log.left_out(), collisions);
  EXPECT_EQ(log.damaged(), 1u);
  EXPECT_EQ(got.damage, 1u);
}

}  // namespace
}  // namespace sculpt::view