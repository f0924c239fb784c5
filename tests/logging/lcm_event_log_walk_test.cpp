// for_each_event: every valid event of a log in file order, and each place that is not one
// with its byte offset, the walk going on past it (what sculpt replay and sculpt render --log
// both read logs with).

#include "sculpt/logging/event_log_walk.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/scratch_dir.hpp"

namespace sculpt::logging {
namespace {

using Bytes = std::vector<std::uint8_t>;

void put_be(Bytes& out, std::uint64_t value, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

/// One event in LCM's log format (event_log_reader.hpp), payload bytes 0, 1, 2, ...
Bytes event_bytes(std::int64_t number, const std::string& channel, std::size_t payload) {
  Bytes out;
  put_be(out, kLogSyncWord, 4);
  put_be(out, static_cast<std::uint64_t>(number), 8);
  put_be(out, static_cast<std::uint64_t>(1000 + number), 8);
  put_be(out, channel.size(), 4);
  put_be(out, payload, 4);
  out.insert(out.end(), channel.begin(), channel.end());
  for (std::size_t i = 0; i < payload; ++i) out.push_back(static_cast<std::uint8_t>(i));
  return out;
}

std::string write_file(const std::string& name, const Bytes& bytes) {
  static const test::ScratchDir kScratch("sculpt_walk_test_");  // this process's, removed when it exits
  const std::string path = (kScratch.path() / name).string();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

struct Walk {
  std::vector<std::pair<std::uint64_t, std::string>> events;  // offset, channel
  std::vector<std::pair<std::uint64_t, std::string>> damage;  // offset, what
  EventLogTotals totals;
};

Walk walk(const std::string& path) {
  Walk w;
  w.totals = for_each_event(
      path, [&](const LogEvent& e) { w.events.emplace_back(e.offset, e.channel); },
      [&](std::uint64_t offset, const std::string& what) { w.damage.emplace_back(offset, what); });
  return w;
}

TEST(EventLogWalk, VisitsEveryEventInFileOrder) {
  Bytes log;
  std::vector<std::uint64_t> offsets;
  for (int i = 0; i < 3; ++i) {
    offsets.push_back(log.size());
    const Bytes e = event_bytes(i, i == 1 ? "SCULPT_GLOVE" : "SCULPT_COLLISION", 10 + static_cast<std::size_t>(i));
    log.insert(log.end(), e.begin(), e.end());
  }
  const Walk w = walk(write_file("whole.lcmlog", log));
  ASSERT_EQ(w.events.size(), 3u);
  EXPECT_EQ(w.events[0], std::make_pair(offsets[0], std::string("SCULPT_COLLISION")));
  EXPECT_EQ(w.events[1], std::make_pair(offsets[1], std::string("SCULPT_GLOVE")));
  EXPECT_EQ(w.events[2], std::make_pair(offsets[2], std::string("SCULPT_COLLISION")));
  EXPECT_TRUE(w.damage.empty());
  EXPECT_EQ(w.totals.file_size, log.size());
  EXPECT_EQ(w.totals.skipped_bytes, 0u);
  EXPECT_EQ(w.totals.corrupt, 0u);
}

TEST(EventLogWalk, GoesOnPastDamageAndNamesWhereItWas) {
  Bytes log;
  std::vector<std::uint64_t> offsets;
  for (int i = 0; i < 4; ++i) {
    offsets.push_back(log.size());
    const Bytes e = event_bytes(i, "SCULPT_COLLISION", 16);
    log.insert(log.end(), e.begin(), e.end());
  }
  log[offsets[1]] ^= 0xFF;     // the second event's sync word broken
  log.resize(log.size() - 5);  // and the last one cut short, as a crash leaves it
  const std::string path = write_file("damaged.lcmlog", log);
  const Walk w = walk(path);
  ASSERT_EQ(w.events.size(), 2u);
  EXPECT_EQ(w.events[0].first, offsets[0]);
  EXPECT_EQ(w.events[1].first, offsets[2]);
  ASSERT_EQ(w.damage.size(), 2u);
  EXPECT_EQ(w.damage[0].first, offsets[1]);
  EXPECT_EQ(w.damage[0].second.rfind(path + ": byte offset " + std::to_string(offsets[1]) + ": ", 0), 0u)
      << w.damage[0].second;
  EXPECT_EQ(w.damage[1].first, offsets[3]);
  EXPECT_EQ(w.totals.corrupt, 2u);
  EXPECT_GT(w.totals.skipped_bytes, 0u);
  EXPECT_EQ(w.totals.file_size, log.size());
}

TEST(EventLogWalk, AMissingFileThrowsNamingIt) {
  const std::string path = (std::filesystem::temp_directory_path() / "sculpt_walk_test_absent.lcmlog").string();
  try {
    walk(path);
    FAIL() << "no throw";
  } catch (const LogFileError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::logging
