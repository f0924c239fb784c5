// The durable log's checks (event_check.hpp): each event's CRC-32 in a SCULPT_CHECK event after
// the log's first event and at each flush, and the walk that hands an event on only once its
// check matches. The truth for the CRC is zlib's crc32 over the file's own bytes.

#include "sculpt/logging/event_check.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/durable_log.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt_lcm/log_check_t.hpp"
#include "support/scratch_dir.hpp"

namespace sculpt::logging {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::string check_log_path(const std::string& name) {
  static const test::ScratchDir kScratch("sculpt_check_test_");  // this process's, removed when it exits
  return (kScratch.path() / name).string();
}

Bytes read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A session as the station writes one: the header, `ticks` / 2 ticks, a flush, the rest, the
// stop. On disk (10 ticks): header, check, t0..t4, check, t5..t9, check.
std::string checked_log(const std::string& name, int ticks = 10) {
  DurableLogConfig config;
  config.path = check_log_path(name);
  config.flush_interval = std::chrono::hours(1);  // only the calls below flush
  DurableLog log(config);
  sculpt_lcm::session_header_t header{};
  header.schema = sculpt_lcm::session_header_t::SCHEMA;
  header.version = "check test";
  log.write_session_header(header);
  TickRecord tick;
  for (int i = 0; i < ticks; ++i) {
    tick.tick = i;
    tick.utime = 1'700'000'000'000'000 + i;
    tick.tick_time_us = 100.0F + static_cast<float>(i);
    EXPECT_TRUE(log.record(tick));
    if (i == ticks / 2 - 1) log.flush_now();
  }
  log.stop();
  EXPECT_EQ(log.counters().checks, 3u);
  return config.path;
}

// Every event of `path` as the bytes hold them, checks included.
std::vector<LogEvent> raw_events(const std::string& path) {
  EventLogReader reader(path);
  std::vector<LogEvent> events;
  LogEvent event;
  while (reader.next(event) == EventLogReader::Result::kEvent) events.push_back(event);
  return events;
}

struct Seen {
  std::vector<LogEvent> events;
  std::vector<std::pair<std::uint64_t, std::string>> damage;  // offset, what
  std::vector<std::uint64_t> order;                           // every offset handed on, in order
  EventLogTotals totals;
};

Seen walk_checked(const std::string& path) {
  Seen seen;
  seen.totals = for_each_event(
      path,
      [&](const LogEvent& e) {
        seen.events.push_back(e);
        seen.order.push_back(e.offset);
      },
      [&](std::uint64_t offset, const std::string& what) {
        seen.damage.emplace_back(offset, what);
        seen.order.push_back(offset);
      });
  return seen;
}

std::vector<std::int64_t> tick_numbers(const Seen& seen) {
  std::vector<std::int64_t> ticks;
  for (const LogEvent& e : seen.events) {
    if (e.channel == kTickChannel) ticks.push_back(e.number);
  }
  return ticks;
}

TEST(EventCheck, EachCheckHoldsZlibsCrcOfTheFilesOwnBytesOfItsEvents) {
  const std::string path = checked_log("crc.lcmlog");
  const Bytes file = read_bytes(path);
  const std::vector<LogEvent> events = raw_events(path);
  ASSERT_EQ(events.size(), 14u);
  std::vector<std::string> channels;
  for (const LogEvent& e : events) channels.push_back(e.channel);
  const std::string s = kSessionChannel, c = kCheckChannel, t = kTickChannel;
  EXPECT_EQ(channels, (std::vector<std::string>{s, c, t, t, t, t, t, c, t, t, t, t, t, c}));
  std::size_t checked = 0;
  for (const LogEvent& check_event : events) {
    if (check_event.channel != kCheckChannel) continue;
    sculpt_lcm::log_check_t check;
    std::string error;
    ASSERT_TRUE(decode(check_event, check, error)) << error;
    for (std::int32_t k = 0; k < check.count; ++k) {
      const auto it = std::find_if(events.begin(), events.end(),
                                   [&](const LogEvent& e) { return e.number == check.first_event + k; });
      ASSERT_NE(it, events.end());
      ASSERT_NE(it->channel, kCheckChannel) << "a check does not check a check";
      const uLong truth =
          ::crc32(::crc32(0L, Z_NULL, 0), file.data() + it->offset, static_cast<uInt>(end_of(*it) - it->offset));
      EXPECT_EQ(static_cast<std::uint32_t>(check.crc[static_cast<std::size_t>(k)]), static_cast<std::uint32_t>(truth))
          << "event " << it->number;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 11u) << "the header and the ten ticks, each once";
  // The walk hands on the eleven, checked, and keeps the checks to itself.
  const Seen seen = walk_checked(path);
  EXPECT_EQ(seen.events.size(), 11u);
  EXPECT_TRUE(seen.damage.empty());
  EXPECT_EQ(seen.totals.failed_checks, 0u);
}

// A bit flipped inside a well-formed field passes every range check (100.0 to 100.00001 is a
// tick time like any other); against its check it is damage, in its place in the file, and
// every other event still goes on.
TEST(EventCheck, AFlippedBitInsideAFieldIsDamageAtThatEventAndTheRestGoOn) {
  const std::string path = checked_log("flipped.lcmlog");
  const std::vector<LogEvent> events = raw_events(path);
  const LogEvent& victim = events[4];  // t2
  ASSERT_EQ(victim.channel, kTickChannel);
  Bytes file = read_bytes(path);
  file[end_of(victim) - 1] ^= 0x01;  // the last payload byte, inside a field of tick_stats_t
  write_bytes(path, file);
  {
    // The reader alone sees a valid event there.
    const std::vector<LogEvent> raw = raw_events(path);
    ASSERT_EQ(raw.size(), 14u);
  }
  const Seen seen = walk_checked(path);
  ASSERT_EQ(seen.damage.size(), 1u);
  EXPECT_EQ(seen.totals.left_out, 0u);
  EXPECT_EQ(seen.damage[0].first, victim.offset);
  EXPECT_NE(seen.damage[0].second.find("byte offset " + std::to_string(victim.offset) + ": event " +
                                       std::to_string(victim.number) + " on SCULPT_TICK does not match its check"),
            std::string::npos)
      << seen.damage[0].second;
  EXPECT_EQ(seen.events.size(), 10u);
  const std::vector<std::int64_t> ticks = tick_numbers(seen);
  EXPECT_EQ(ticks.size(), 9u);
  EXPECT_EQ(std::count(ticks.begin(), ticks.end(), victim.number), 0);
  EXPECT_TRUE(std::is_sorted(seen.order.begin(), seen.order.end())) << "damage in its place among the events";
  EXPECT_EQ(seen.totals.failed_checks, 1u);
  EXPECT_EQ(seen.totals.corrupt, 1u);
}

// A crash leaves the events written since the last check, and perhaps half an event: the
// whole ones go on unchecked, as before checks; the half is damage, as before.
TEST(EventCheck, ACrashsTailAfterTheLastCheckGoesOnUnchecked) {
  const std::string path = checked_log("cut.lcmlog");
  const std::vector<LogEvent> events = raw_events(path);
  const LogEvent& t7 = events[10];
  ASSERT_EQ(t7.channel, kTickChannel);
  const Bytes whole = read_bytes(path);
  // Inside t7's header, and inside its payload (the header whole, its length past the end).
  for (const std::uint64_t cut : {t7.offset + 20, end_of(t7) - 5}) {
    Bytes file(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut));
    write_bytes(path, file);
    const Seen seen = walk_checked(path);
    EXPECT_EQ(tick_numbers(seen),
              (std::vector<std::int64_t>{events[2].number, events[3].number, events[4].number, events[5].number,
                                         events[6].number, events[8].number, events[9].number}))
        << "cut at " << cut;
    ASSERT_EQ(seen.damage.size(), 1u) << "cut at " << cut;
    EXPECT_EQ(seen.damage[0].first, t7.offset);
    EXPECT_NE(seen.damage[0].second.find("truncated event"), std::string::npos) << seen.damage[0].second;
    EXPECT_EQ(seen.totals.failed_checks, 0u);
    EXPECT_TRUE(std::is_sorted(seen.order.begin(), seen.order.end()));
  }
  Bytes file = whole;

  file.resize(t7.offset);  // a cut between two events: nothing is damaged
  write_bytes(path, file);
  const Seen clean = walk_checked(path);
  EXPECT_EQ(tick_numbers(clean).size(), 7u);
  EXPECT_TRUE(clean.damage.empty());
}

// A length changed in the last event before the log's last check reaches into that check, which
// the reader then cannot see: the event (read with the check's first bytes as its own) and the
// others after the check before are not a crash's tail, since what follows them is not bytes
// running out, so they are damage, not handed on.
TEST(EventCheck, ALastCheckSwallowedByALengthLeavesItsEventsOut) {
  const std::string path = checked_log("swallowed.lcmlog");
  const std::vector<LogEvent> events = raw_events(path);
  const LogEvent& t9 = events[12];
  ASSERT_EQ(t9.channel, kTickChannel);
  ASSERT_EQ(events[13].channel, kCheckChannel);
  Bytes file = read_bytes(path);
  file[t9.offset + kLogHeaderSize - 1] ^= 0x10;  // its data length, 16 bytes longer
  write_bytes(path, file);
  const Seen seen = walk_checked(path);
  EXPECT_EQ(tick_numbers(seen), (std::vector<std::int64_t>{events[2].number, events[3].number, events[4].number,
                                                           events[5].number, events[6].number}));
  ASSERT_EQ(seen.damage.size(), 2u);
  EXPECT_EQ(seen.damage[0].first, events[8].offset);
  EXPECT_NE(seen.damage[0].second.find("5 events, to the one at byte offset " + std::to_string(t9.offset) +
                                       ", are covered by no check (damage follows them to the end of the log"),
            std::string::npos)
      << seen.damage[0].second;
  EXPECT_EQ(seen.damage[1].first, end_of(t9) + 16);
  EXPECT_TRUE(std::is_sorted(seen.order.begin(), seen.order.end()));
  EXPECT_EQ(seen.totals.left_out, 5u);
  EXPECT_EQ(seen.totals.corrupt, seen.damage.size());
}

// A check that is itself damaged checks nothing: the reader says so, and its events, which no
// check now vouches for, are damage too (one report for the run), not handed on.
TEST(EventCheck, ADamagedCheckAndTheEventsItCheckedAreDamage) {
  const std::string path = checked_log("bad-check.lcmlog");
  const std::vector<LogEvent> events = raw_events(path);
  const LogEvent& check = events[7];
  ASSERT_EQ(check.channel, kCheckChannel);
  Bytes file = read_bytes(path);
  const std::uint64_t data_start = end_of(check) - check.data.size();
  file[data_start] ^= 0x80;  // its type fingerprint
  write_bytes(path, file);
  const Seen seen = walk_checked(path);
  // t0..t4, the events the damaged check held, then the check itself, in file order.
  const std::vector<std::int64_t> later{events[8].number, events[9].number, events[10].number, events[11].number,
                                        events[12].number};
  const auto expect_left_out = [&](const Seen& s, const std::string& why) {
    ASSERT_EQ(s.damage.size(), 2u);
    EXPECT_EQ(s.damage[0].first, events[2].offset);
    EXPECT_NE(s.damage[0].second.find("5 events, to the one at byte offset " + std::to_string(events[6].offset) +
                                      ", are covered by no check"),
              std::string::npos)
        << s.damage[0].second;
    EXPECT_EQ(s.damage[1].first, check.offset);
    EXPECT_NE(s.damage[1].second.find(why), std::string::npos) << s.damage[1].second;
    EXPECT_EQ(tick_numbers(s), later) << "only the ticks the next check vouches for";
    EXPECT_EQ(s.totals.failed_checks, 0u);
    EXPECT_EQ(s.totals.left_out, 5u);
    EXPECT_EQ(s.totals.corrupt, 2u) << "the check, and the run it left";
    EXPECT_TRUE(std::is_sorted(s.order.begin(), s.order.end()));
  };
  expect_left_out(seen, "log_check_t");

  // A check that decodes but whose first event is no log's (the largest number, where the end
  // of its span would overflow): the same.
  file[data_start] ^= 0x80;  // the fingerprint as it was
  for (std::size_t b = 0; b < 8; ++b) file[data_start + 8 + b] = b == 0 ? 0x7f : 0xff;
  write_bytes(path, file);
  expect_left_out(walk_checked(path), "a check whose numbers are not a log's (first event 9223372036854775807");

  // A count LCM's decoder would trust (lcm_lengths.hpp): negative, it threw std::length_error
  // out of the walk, refusing the whole log; past 2^29 it overflowed decode's int size check
  // and read past the payload. Each is the same damage, named.
  for (std::size_t b = 0; b < 8; ++b) file[data_start + 8 + b] = 0;  // first event 0
  for (const std::uint32_t count : {0xFFFFFFFFu, 0x80000000u, 0x20000001u, 0x7FFFFFFFu, 6u}) {
    SCOPED_TRACE(count);
    for (std::size_t b = 0; b < 4; ++b) file[data_start + 16 + b] = static_cast<std::uint8_t>(count >> (24 - 8 * b));
    write_bytes(path, file);
    expect_left_out(walk_checked(path),
                    "crc's count " + std::to_string(static_cast<std::int32_t>(count)) + " at payload byte 16");
  }
}

// Every byte of a checked log flipped in turn: whatever the flip hits (a sync word, a length, a
// number, a time, a payload, a check's channel or contents), no event is handed on with bytes
// other than those written at its offset, and a flip inside an event is always reported. A flip
// inside a check costs its events (reported), or nothing (its own number or time, which nothing
// reads; the last check's name, which makes its events a crash's tail: unchanged, unchecked).
TEST(EventCheck, NoFlippedByteAnywhereHandsOnAChangedEvent) {
  // Two ticks a span: every kind of event and check, in a third of the bytes (a sanitizer build
  // walks each of them).
  const std::string path = checked_log("every-byte.lcmlog", 4);
  const Bytes original = read_bytes(path);
  const std::vector<LogEvent> written = raw_events(path);
  const auto written_at = [&](std::uint64_t offset) -> const LogEvent* {
    for (const LogEvent& e : written) {
      if (e.offset == offset) return &e;
    }
    return nullptr;
  };
  const std::string flipped_path = check_log_path("every-byte-flipped.lcmlog");
  std::size_t in_events = 0;
  for (std::size_t at = 0; at < original.size(); ++at) {
    const LogEvent* hit = nullptr;
    for (const LogEvent& e : written) {
      if (at >= e.offset && at < end_of(e)) hit = &e;
    }
    ASSERT_NE(hit, nullptr);
    Bytes flipped = original;
    flipped[at] ^= 0x10;
    write_bytes(flipped_path, flipped);
    const Seen seen = walk_checked(flipped_path);
    for (const LogEvent& e : seen.events) {
      const LogEvent* was = written_at(e.offset);
      ASSERT_NE(was, nullptr) << "byte " << at << ": an event handed on at offset " << e.offset
                              << ", where none was written";
      if (was->channel == kCheckChannel) {
        // The log's last check, renamed by the flip: with the events after the check before it,
        // a crash's tail to the walk, handed on unchecked and unchanged; under its new name it is
        // no station channel, which every reader passes over.
        ASSERT_EQ(hit, was) << "byte " << at;
        for (const char* station : {kSessionChannel, kGloveChannel, kFingertipChannel, kCollisionChannel, kTickChannel,
                                    kHapticChannel, kCheckChannel}) {
          ASSERT_NE(e.channel, station) << "byte " << at << ": a check handed on as a station channel";
        }
        continue;
      }
      ASSERT_EQ(e.channel, was->channel) << "byte " << at;
      ASSERT_EQ(e.utime, was->utime) << "byte " << at;
      ASSERT_EQ(e.data, was->data) << "byte " << at << " changed the payload of the event at " << e.offset;
    }
    ASSERT_TRUE(std::is_sorted(seen.order.begin(), seen.order.end())) << "byte " << at;
    ASSERT_EQ(seen.totals.corrupt, seen.damage.size()) << "byte " << at << ": every report counted once";
    if (hit->channel != kCheckChannel) {
      ++in_events;
      ASSERT_FALSE(seen.damage.empty()) << "byte " << at << " in the event at " << hit->offset << " went unreported";
    }
  }
  EXPECT_GT(in_events, original.size() / 2);
}

// A log with no check after its first event (lcm-logger's, or the durable log's before checks)
// reads as it always did: every event, nothing held back, nothing called damage.
TEST(EventCheck, ALogWithoutChecksReadsAsBefore) {
  const std::string path = check_log_path("unchecked.lcmlog");
  {
    lcm::LogFile file(path, "w");
    ASSERT_TRUE(file.good());
    std::vector<std::uint8_t> data(40, 7);
    for (int i = 0; i < 5; ++i) {
      lcm::LogEvent event;
      event.eventnum = i;
      event.timestamp = 1000 + i;
      event.channel = i == 0 ? kSessionChannel : kTickChannel;
      event.datalen = static_cast<std::int32_t>(data.size());
      event.data = data.data();
      ASSERT_EQ(file.writeEvent(&event), 0);
    }
  }
  Bytes file = read_bytes(path);
  file[file.size() - 1] ^= 0x01;  // unseen without a check
  write_bytes(path, file);
  const Seen seen = walk_checked(path);
  EXPECT_EQ(seen.events.size(), 5u);
  EXPECT_TRUE(seen.damage.empty());
  EXPECT_EQ(seen.totals.failed_checks, 0u);
}

}  // namespace
}  // namespace sculpt::logging
