// The lengths inside an LCM payload, checked before lcm-gen's decoder trusts them: every
// message LCM itself encodes passes, and every count or string length that does not fit what
// is left of the payload is an error naming the field and its byte, never a throw or a read
// past the payload (the sanitizer builds run this).

#include "sculpt/logging/lcm_lengths.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt_lcm/log_check_t.hpp"
#include "sculpt_lcm/session_header_t.hpp"

namespace sculpt::logging {
namespace {

template <typename Message>
LogEvent encoded(const Message& message) {
  LogEvent event;
  event.channel = "TEST";
  event.offset = 4096;
  event.data.resize(static_cast<std::size_t>(message.getEncodedSize()));
  EXPECT_EQ(message.encode(event.data.data(), 0, static_cast<int>(event.data.size())),
            static_cast<int>(event.data.size()));
  return event;
}

void put_int32(std::vector<std::uint8_t>& data, std::size_t at, std::int32_t value) {
  const auto bits = static_cast<std::uint32_t>(value);
  for (std::size_t b = 0; b < 4; ++b) data[at + b] = static_cast<std::uint8_t>(bits >> (24 - 8 * b));
}

sculpt_lcm::session_header_t header_with(const std::string& version, const std::string& path, const std::string& text) {
  sculpt_lcm::session_header_t h{};
  h.schema = sculpt_lcm::session_header_t::SCHEMA;
  h.version = version;
  h.scene_path = path;
  h.scene_text = text;
  h.model_points = 3203;
  h.reduced_ratio = 1.0;
  return h;
}

TEST(LcmLengths, EveryMessageLcmEncodesPassesAndDecodesAsWritten) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 200; ++trial) {
    sculpt_lcm::log_check_t check{};
    check.first_event = static_cast<std::int64_t>(random() % 100000);
    check.count = static_cast<std::int32_t>(random() % 300);
    for (std::int32_t k = 0; k < check.count; ++k) check.crc.push_back(static_cast<std::int32_t>(random()));
    const LogEvent check_event = encoded(check);
    EXPECT_EQ(payload_lengths_problem(check, check_event.data), "");
    sculpt_lcm::log_check_t check_back;
    std::string error;
    ASSERT_TRUE(decode(check_event, check_back, error)) << error;
    EXPECT_EQ(check_back.crc, check.crc);

    const auto text = [&] { return std::string(random() % 50, static_cast<char>('a' + random() % 26)); };
    const sculpt_lcm::session_header_t header = header_with(text(), text(), text());
    const LogEvent header_event = encoded(header);
    EXPECT_EQ(payload_lengths_problem(header, header_event.data), "");
    sculpt_lcm::session_header_t header_back;
    ASSERT_TRUE(decode(header_event, header_back, error)) << error;
    EXPECT_EQ(header_back.version, header.version);
    EXPECT_EQ(header_back.scene_path, header.scene_path);
    EXPECT_EQ(header_back.scene_text, header.scene_text);
    EXPECT_EQ(header_back.model_points, header.model_points);
  }
}

TEST(LcmLengths, ACheckCountThatDoesNotFitIsAnErrorNamingIt) {
  sculpt_lcm::log_check_t check{};
  check.first_event = 12;
  check.count = 3;
  check.crc = {1, 2, 3};
  const LogEvent good = encoded(check);  // 8 fingerprint + 8 first_event + 4 count + 12
  ASSERT_EQ(good.data.size(), 32u);
  // Negative (vector::resize threw), past 2^29 (decode's int size overflowed and it read past
  // the payload), the largest, and one element more than the payload holds.
  for (const std::int32_t count : {-1, INT32_MIN, (1 << 29) + 1, INT32_MAX, 4}) {
    SCOPED_TRACE(count);
    LogEvent bad = good;
    put_int32(bad.data, 16, count);
    sculpt_lcm::log_check_t out;
    std::string error;
    EXPECT_FALSE(decode(bad, out, error));
    EXPECT_EQ(
        error.rfind("TEST event at byte offset 4096: crc's count " + std::to_string(count) + " at payload byte 16 ", 0),
        0u)
        << error;
    EXPECT_NE(error.find(count < 0 ? "is negative" : "needs " + std::to_string(4 * std::int64_t{count}) + " bytes"),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("(12 of the payload's 32 bytes are left)"), std::string::npos) << error;
  }
  // The count the payload holds exactly still decodes; one fewer leaves trailing bytes, which
  // decode() reports itself.
  LogEvent fewer = good;
  put_int32(fewer.data, 16, 2);
  sculpt_lcm::log_check_t out;
  std::string error;
  EXPECT_EQ(payload_lengths_problem(out, fewer.data), "");
  EXPECT_FALSE(decode(fewer, out, error));
  EXPECT_NE(error.find("4 trailing bytes"), std::string::npos) << error;
}

TEST(LcmLengths, AStringLengthThatDoesNotFitIsAnErrorNamingTheField) {
  const sculpt_lcm::session_header_t header = header_with("v1", "scene.toml", "[model]");
  const LogEvent good = encoded(header);
  // Payload: fingerprint 8, utime 8, schema 4, then each string as int32 length (its NUL
  // counted) and its bytes.
  const std::size_t version_at = 20, path_at = version_at + 4 + 3, text_at = path_at + 4 + 11;
  struct Case {
    const char* field;
    std::size_t at;
  };
  for (const Case& c : {Case{"version", version_at}, Case{"scene_path", path_at}, Case{"scene_text", text_at}}) {
    for (const std::int32_t length : {0, -1, INT32_MIN, INT32_MAX, 100000}) {
      SCOPED_TRACE(std::string(c.field) + " " + std::to_string(length));
      LogEvent bad = good;
      put_int32(bad.data, c.at, length);
      sculpt_lcm::session_header_t out;
      std::string error;
      EXPECT_FALSE(decode(bad, out, error));
      EXPECT_NE(error.find(std::string(c.field) + "'s length " + std::to_string(length) + " at payload byte " +
                           std::to_string(c.at) + (length < 1 ? " is below 1" : " needs")),
                std::string::npos)
          << error;
    }
  }
}

TEST(LcmLengths, APayloadThatEndsBeforeALengthIsLeftToDecodeToCallShort) {
  const LogEvent good = encoded(header_with("v1", "scene.toml", "[model]"));
  sculpt_lcm::session_header_t out;
  for (const std::size_t size : {8u, 12u, 20u, 22u, 30u}) {
    SCOPED_TRACE(size);
    LogEvent cut = good;
    cut.data.resize(size);
    EXPECT_EQ(payload_lengths_problem(out, cut.data), "");
    std::string error;
    EXPECT_FALSE(decode(cut, out, error));
    EXPECT_NE(error.find("does not decode as session_header_t (too short or malformed)"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace sculpt::logging
