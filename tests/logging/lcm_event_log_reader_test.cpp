// EventLogReader on logs written by LCM's own writer (lcm::LogFile), intact and damaged in
// known ways: every complaint must name the byte offset where the damage is.

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "support/scratch_dir.hpp"

namespace sculpt::logging {
namespace {

using Bytes = std::vector<std::uint8_t>;
using Result = EventLogReader::Result;

// This process's folder, removed when it exits.
std::string reader_log_path(const std::string& name) {
  static const test::ScratchDir kScratch("sculpt_reader_test_");
  return (kScratch.path() / name).string();
}

template <typename Message>
Bytes encode(const Message& message) {
  Bytes bytes(static_cast<std::size_t>(message.getEncodedSize()));
  EXPECT_EQ(message.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return bytes;
}

Bytes collision_bytes(std::int64_t tick) {
  CollisionRecord record;
  record.utime = 1'000'000 + tick;
  record.tick = tick;
  record.contact_index = static_cast<std::int32_t>(tick * 3);
  record.force = {0.1 * static_cast<double>(tick), -0.2, 0.3};
  sculpt_lcm::collision_event_t message{};
  to_lcm(record, message);
  return encode(message);
}

Bytes tick_bytes(std::int64_t tick) {
  TickRecord record;
  record.utime = 1'000'000 + tick;
  record.tick = tick;
  sculpt_lcm::tick_stats_t message{};
  to_lcm(record, message);
  return encode(message);
}

struct Written {
  std::vector<std::uint64_t> offsets;  // of each event's sync word
  std::uint64_t size = 0;
};

/// Writes `events` (channel, payload) with LCM's own writer, timestamps 1000 + i.
Written write_log(const std::string& path, const std::vector<std::pair<std::string, Bytes>>& events) {
  Written written;
  lcm::LogFile log(path, "w");
  EXPECT_TRUE(log.good());
  std::int64_t i = 0;
  for (const auto& [channel, payload] : events) {
    lcm::LogEvent event;
    event.eventnum = i;
    event.timestamp = 1000 + i;
    event.channel = channel;
    event.datalen = static_cast<std::int32_t>(payload.size());
    event.data = const_cast<std::uint8_t*>(payload.data());
    EXPECT_EQ(log.writeEvent(&event), 0);
    written.offsets.push_back(written.size);
    written.size += kLogHeaderSize + channel.size() + payload.size();
    ++i;
  }
  return written;
}

/// Five alternating collision and tick events.
Written write_mixed(const std::string& path) {
  std::vector<std::pair<std::string, Bytes>> events;
  for (int i = 0; i < 5; ++i) {
    if (i % 2 == 0) {
      events.emplace_back(kCollisionChannel, collision_bytes(i));
    } else {
      events.emplace_back(kTickChannel, tick_bytes(i));
    }
  }
  return write_log(path, events);
}

Bytes load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void save(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void put_i32(Bytes& bytes, std::uint64_t at, std::int32_t value) {
  const auto u = static_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) bytes[at + static_cast<std::uint64_t>(i)] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
}

std::string offset_text(std::uint64_t offset) { return "byte offset " + std::to_string(offset) + ": "; }

TEST(EventLogReader, MissingFileThrowsNamingThePath) {
  const std::string path = reader_log_path("does_not_exist.lcmlog");
  try {
    EventLogReader reader(path);
    FAIL() << "no throw";
  } catch (const LogFileError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// A folder and a device open and stat without an error, so errno held whatever an earlier call
// left: `sculpt report /tmp` said "not a readable regular file: No such file or directory".
TEST(EventLogReader, AFolderOrADeviceIsNamedForWhatItIs) {
  const auto message = [](const std::string& path) {
    try {
      EventLogReader reader(path);
    } catch (const LogFileError& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  errno = ENOENT;  // as a failed lookup before the call would leave it
  const std::string folder = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(message(folder), folder + ": cannot read: a directory, not a regular file");
  errno = ENOENT;
  EXPECT_EQ(message("/dev/null"), "/dev/null: cannot read: a character device, not a regular file");
}

// A FIFO named as a log held the open until a writer came: `sculpt replay`, `render --log` and
// `report` waited for ever. It is refused at once, as a model or a scene is.
TEST(EventLogReader, AFifoIsRefusedWithoutWaitingForAWriter) {
  const std::string path = reader_log_path("fifo.lcmlog");
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0) << std::strerror(errno);
  try {
    EventLogReader reader(path);
    ADD_FAILURE() << "no throw";
  } catch (const LogFileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot read: a FIFO, not a regular file");
  }
  std::filesystem::remove(path);
}

TEST(EventLogReader, EmptyFileIsTheEnd) {
  const std::string path = reader_log_path("empty.lcmlog");
  save(path, {});
  EventLogReader reader(path);
  LogEvent event;
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.corrupt_events(), 0u);
  EXPECT_EQ(reader.skipped_bytes(), 0u);
}

TEST(EventLogReader, ReadsEveryEventWithItsOffset) {
  const std::string path = reader_log_path("intact.lcmlog");
  const Written written = write_mixed(path);
  EventLogReader reader(path);
  LogEvent event;
  for (std::size_t i = 0; i < 5; ++i) {
    ASSERT_EQ(reader.next(event), Result::kEvent) << reader.error();
    EXPECT_EQ(event.offset, written.offsets[i]);
    EXPECT_EQ(event.number, static_cast<std::int64_t>(i));
    EXPECT_EQ(event.utime, 1000 + static_cast<std::int64_t>(i));
    EXPECT_EQ(event.channel, i % 2 == 0 ? kCollisionChannel : kTickChannel);
    if (i % 2 == 0) {
      sculpt_lcm::collision_event_t message{};
      std::string error;
      ASSERT_TRUE(decode(event, message, error)) << error;
      EXPECT_EQ(message.tick, static_cast<std::int64_t>(i));
      EXPECT_EQ(message.contact_index, static_cast<std::int32_t>(i * 3));
    } else {
      sculpt_lcm::tick_stats_t message{};
      std::string error;
      ASSERT_TRUE(decode(event, message, error)) << error;
      EXPECT_EQ(message.tick, static_cast<std::int64_t>(i));
    }
  }
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.corrupt_events(), 0u);
  EXPECT_EQ(reader.skipped_bytes(), 0u);
}

TEST(EventLogReader, StartsAtTheEndOfAnEventAnEarlierReaderReturned) {
  const std::string path = reader_log_path("resumed.lcmlog");
  const Written written = write_mixed(path);
  LogEvent event;
  {
    EventLogReader first(path);
    ASSERT_EQ(first.next(event), Result::kEvent);
    ASSERT_EQ(first.next(event), Result::kEvent);
  }
  EXPECT_EQ(end_of(event), written.offsets[2]);  // LCM's writer put the third event there
  EventLogReader resumed(path, end_of(event));
  for (std::size_t i = 2; i < 5; ++i) {
    ASSERT_EQ(resumed.next(event), Result::kEvent) << resumed.error();
    EXPECT_EQ(event.offset, written.offsets[i]);
    EXPECT_EQ(event.number, static_cast<std::int64_t>(i));
  }
  EXPECT_EQ(end_of(event), written.size);
  EXPECT_EQ(resumed.next(event), Result::kEnd);

  EventLogReader at_end(path, written.size);
  EXPECT_EQ(at_end.next(event), Result::kEnd);
  try {
    EventLogReader past(path, written.size + 1);
    FAIL() << "no throw";
  } catch (const LogFileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("byte offset " + std::to_string(written.size + 1)), std::string::npos) << what;
  }
}
TEST(EventLogReader, TruncatedInsideAHeader) {
  const std::string path = reader_log_path("truncated_header.lcmlog");
  const Written written = write_mixed(path);
  std::filesystem::resize_file(path, written.offsets[4] + 10);
  EventLogReader reader(path);
  LogEvent event;
  for (int i = 0; i < 4; ++i) ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kCorrupt);
  EXPECT_EQ(reader.error(),
            path + ": " + offset_text(written.offsets[4]) + "truncated event header: needs 28 bytes, 10 left");
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.skipped_bytes(), 10u);
  EXPECT_EQ(reader.corrupt_events(), 1u);
}

TEST(EventLogReader, TruncatedInsideThePayload) {
  const std::string path = reader_log_path("truncated_data.lcmlog");
  const Written written = write_mixed(path);
  const std::uint64_t cut = written.offsets[4] + kLogHeaderSize + std::string(kCollisionChannel).size() + 5;
  std::filesystem::resize_file(path, cut);
  EventLogReader reader(path);
  LogEvent event;
  for (int i = 0; i < 4; ++i) ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kCorrupt);
  const std::uint64_t full = written.size - written.offsets[4];
  EXPECT_EQ(reader.error(), path + ": " + offset_text(written.offsets[4]) + "truncated event: needs " +
                                std::to_string(full) + " bytes, " + std::to_string(cut - written.offsets[4]) + " left");
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.skipped_bytes(), cut - written.offsets[4]);
}

TEST(EventLogReader, BadSyncWordIsReportedAndSkipped) {
  const std::string path = reader_log_path("bad_sync.lcmlog");
  const Written written = write_mixed(path);
  Bytes bytes = load(path);
  bytes[written.offsets[2]] = 0x12;  // 0xEDA1DA01 -> 0x12A1DA01
  save(path, bytes);
  EventLogReader reader(path);
  LogEvent event;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kCorrupt);
  EXPECT_EQ(reader.error(),
            path + ": " + offset_text(written.offsets[2]) + "bad sync word 0x12A1DA01 (expected 0xEDA1DA01)");
  ASSERT_EQ(reader.next(event), Result::kEvent) << reader.error();
  EXPECT_EQ(event.offset, written.offsets[3]);
  EXPECT_EQ(event.number, 3);
  ASSERT_EQ(reader.next(event), Result::kEvent);
  EXPECT_EQ(event.number, 4);
  EXPECT_EQ(reader.next(event), Result::kEnd);
  EXPECT_EQ(reader.skipped_bytes(), written.offsets[3] - written.offsets[2]);
  EXPECT_EQ(reader.corrupt_events(), 1u);
}

TEST(EventLogReader, GarbageBetweenEventsIsSkipped) {
  const std::string path = reader_log_path("garbage.lcmlog");
  const Written written = write_mixed(path);
  Bytes bytes = load(path);
  Bytes garbage(100);
  std::mt19937 random(7);
  for (auto& b : garbage) b = static_cast<std::uint8_t>(random());
  garbage[40] = 0xED;  // a sync word whose header is nonsense must not fool the resync
  garbage[41] = 0xA1;
  garbage[42] = 0xDA;
  garbage[43] = 0x01;
  bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(written.offsets[2]), garbage.begin(), garbage.end());
  save(path, bytes);
  EventLogReader reader(path);
  LogEvent event;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kCorrupt);
  EXPECT_NE(reader.error().find(offset_text(written.offsets[2])), std::string::npos) << reader.error();
  ASSERT_EQ(reader.next(event), Result::kEvent) << reader.error();
  EXPECT_EQ(event.number, 2);
  EXPECT_EQ(event.offset, written.offsets[2] + 100);
  EXPECT_EQ(reader.skipped_bytes(), 100u);
}

TEST(EventLogReader, NegativeAndHugeLengthsAreRejectedWithoutAllocating) {
  struct Case {
    std::uint64_t field;  // offset of the length field within the header
    std::int32_t value;
    std::string message;
  };
  const std::vector<Case> cases = {
      {20, -5, "channel length -5"},
      {20, 100000, "channel length 100000"},
      {24, -3, "data length -3"},
      {24, 0x7FFFFFF0, ""},  // the message depends on the size left; checked below
  };
  for (const Case& c : cases) {
    const std::string path = reader_log_path("lengths.lcmlog");
    const Written written = write_mixed(path);
    Bytes bytes = load(path);
    put_i32(bytes, written.offsets[1] + c.field, c.value);
    save(path, bytes);
    EventLogReader reader(path);
    LogEvent event;
    ASSERT_EQ(reader.next(event), Result::kEvent);
    ASSERT_EQ(reader.next(event), Result::kCorrupt);
    std::string expected = c.message;
    if (expected.empty()) {
      expected = "truncated event: needs " +
                 std::to_string(kLogHeaderSize + std::string(kTickChannel).size() + 0x7FFFFFF0u) + " bytes, " +
                 std::to_string(written.size - written.offsets[1]) + " left";
    }
    EXPECT_EQ(reader.error(), path + ": " + offset_text(written.offsets[1]) + expected);
    ASSERT_EQ(reader.next(event), Result::kEvent) << reader.error();
    EXPECT_EQ(event.number, 2);
    EXPECT_EQ(reader.skipped_bytes(), written.offsets[2] - written.offsets[1]);
  }
}

TEST(EventLogReader, GarbagePayloadOnTheCollisionChannelNamesTheOffset) {
  const std::string path = reader_log_path("garbage_payload.lcmlog");
  Bytes garbage = collision_bytes(1);
  std::mt19937 random(11);
  for (auto& b : garbage) b = static_cast<std::uint8_t>(random());
  const Written written = write_log(path, {{kTickChannel, tick_bytes(0)}, {kCollisionChannel, garbage}});
  EventLogReader reader(path);
  LogEvent event;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  ASSERT_EQ(reader.next(event), Result::kEvent);  // the framing is intact, only the payload is bad
  sculpt_lcm::collision_event_t message{};
  std::string error;
  EXPECT_FALSE(decode(event, message, error));
  const std::string expected =
      std::string(kCollisionChannel) + " event at byte offset " + std::to_string(written.offsets[1]) + ": ";
  EXPECT_TRUE(error.starts_with(expected)) << error;
}

TEST(EventLogReader, WrongTypeOnTheCollisionChannelIsAFingerprintError) {
  const std::string path = reader_log_path("wrong_type.lcmlog");
  const Written written =
      write_log(path, {{kCollisionChannel, collision_bytes(0)}, {kCollisionChannel, tick_bytes(1)}});
  EventLogReader reader(path);
  LogEvent event;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  sculpt_lcm::collision_event_t message{};
  std::string error;
  EXPECT_TRUE(decode(event, message, error)) << error;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  EXPECT_FALSE(decode(event, message, error));
  EXPECT_NE(error.find("SCULPT_COLLISION event at byte offset " + std::to_string(written.offsets[1])),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("type fingerprint"), std::string::npos) << error;
  EXPECT_NE(error.find("collision_event_t"), std::string::npos) << error;
}

TEST(EventLogReader, ShortAndOverlongPayloadsAreDecodeErrors) {
  const std::string path = reader_log_path("short_long.lcmlog");
  Bytes whole = collision_bytes(2);
  Bytes short_payload(whole.begin(), whole.begin() + 20);  // right fingerprint, cut short
  Bytes long_payload = whole;
  long_payload.push_back(0);
  long_payload.push_back(0);
  const Written written = write_log(
      path, {{kCollisionChannel, short_payload}, {kCollisionChannel, long_payload}, {kCollisionChannel, {1, 2, 3}}});
  EventLogReader reader(path);
  LogEvent event;
  sculpt_lcm::collision_event_t message{};
  std::string error;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  EXPECT_FALSE(decode(event, message, error));
  EXPECT_NE(error.find("byte offset 0: payload of 20 bytes does not decode"), std::string::npos) << error;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  EXPECT_FALSE(decode(event, message, error));
  EXPECT_NE(error.find("byte offset " + std::to_string(written.offsets[1]) + ": 2 trailing bytes"), std::string::npos)
      << error;
  ASSERT_EQ(reader.next(event), Result::kEvent);
  EXPECT_FALSE(decode(event, message, error));
  EXPECT_NE(error.find("shorter than a type fingerprint"), std::string::npos) << error;
}

// Seeded random bit flips: never a crash, never a hang, and every byte of the file is either
// part of an event handed out or counted as skipped.
TEST(EventLogReader, RandomBitFlipsNeverBreakTheReader) {
  const std::string path = reader_log_path("flips.lcmlog");
  std::vector<std::pair<std::string, Bytes>> events;
  for (int i = 0; i < 60; ++i) {
    events.emplace_back(i % 3 == 0 ? kCollisionChannel : kTickChannel, i % 3 == 0 ? collision_bytes(i) : tick_bytes(i));
  }
  const Written written = write_log(path, events);
  const Bytes intact = load(path);
  std::mt19937_64 random(20240601);
  for (int trial = 0; trial < 300; ++trial) {
    Bytes bytes = intact;
    const int flips = 1 + static_cast<int>(random() % 40);
    for (int f = 0; f < flips; ++f) {
      const std::uint64_t at = random() % bytes.size();
      bytes[at] ^= static_cast<std::uint8_t>(1u << (random() % 8));
    }
    if (trial % 10 == 0) bytes.resize(random() % bytes.size());  // and sometimes a cut
    save(path, bytes);
    EventLogReader reader(path);
    LogEvent event;
    std::uint64_t consumed = 0;
    std::size_t calls = 0;
    Result result;
    while ((result = reader.next(event)) != Result::kEnd) {
      ASSERT_LT(++calls, bytes.size() + 10) << "no progress, trial " << trial;
      if (result == Result::kCorrupt) {
        EXPECT_NE(reader.error().find("byte offset "), std::string::npos);
        continue;
      }
      consumed += kLogHeaderSize + event.channel.size() + event.data.size();
      std::string error;
      if (event.channel == kCollisionChannel) {
        sculpt_lcm::collision_event_t message{};
        if (decode(event, message, error)) {
          CollisionRecord record;
          (void)from_lcm(message, record);
        }
      } else {
        sculpt_lcm::tick_stats_t message{};
        (void)decode(event, message, error);
      }
    }
    EXPECT_EQ(consumed + reader.skipped_bytes(), bytes.size()) << "trial " << trial;
  }
  (void)written;
}

}  // namespace
}  // namespace sculpt::logging
