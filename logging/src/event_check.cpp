#include "sculpt/logging/event_check.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <limits>

#include "sculpt/logging/event_log_reader.hpp"

namespace sculpt::logging {
namespace {

// zlib's crc32 takes a uInt length: a longer span goes in pieces.
std::uint32_t crc_add(std::uint32_t crc, const std::uint8_t* bytes, std::size_t size) noexcept {
  uLong running = crc;
  while (size > 0) {
    const std::size_t piece = std::min<std::size_t>(size, 1u << 30);
    running = ::crc32(running, bytes, static_cast<uInt>(piece));
    bytes += piece;
    size -= piece;
  }
  return static_cast<std::uint32_t>(running);
}

void put_big_endian(std::uint8_t* out, std::uint64_t value, std::size_t bytes) noexcept {
  for (std::size_t i = 0; i < bytes; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * (bytes - 1 - i)));
}

}  // namespace

std::uint32_t event_crc32(std::int64_t number, std::int64_t utime, std::string_view channel, const std::uint8_t* data,
                          std::size_t size) noexcept {
  std::array<std::uint8_t, kLogHeaderSize> header{};
  put_big_endian(header.data(), kLogSyncWord, 4);
  put_big_endian(header.data() + 4, static_cast<std::uint64_t>(number), 8);
  put_big_endian(header.data() + 12, static_cast<std::uint64_t>(utime), 8);
  put_big_endian(header.data() + 20, channel.size(), 4);
  put_big_endian(header.data() + 24, size, 4);
  std::uint32_t crc = static_cast<std::uint32_t>(::crc32(0L, Z_NULL, 0));
  crc = crc_add(crc, header.data(), header.size());
  crc = crc_add(crc, reinterpret_cast<const std::uint8_t*>(channel.data()), channel.size());
  return crc_add(crc, data, size);
}

bool read_check(const LogEvent& event, sculpt_lcm::log_check_t& check, std::string& error) {
  if (!decode(event, check, error)) return false;
  if (check.count < 0 || static_cast<std::size_t>(check.count) != check.crc.size() || check.first_event < 0 ||
      check.first_event > std::numeric_limits<std::int64_t>::max() - check.count) {
    error = event.channel + " event at byte offset " + std::to_string(event.offset) +
            ": a check whose numbers are not a log's (first event " + std::to_string(check.first_event) + ", count " +
            std::to_string(check.count) + ")";
    return false;
  }
  return true;
}

std::optional<std::uint32_t> checked_crc(const sculpt_lcm::log_check_t& check, std::int64_t number) noexcept {
  if (number < check.first_event || number - check.first_event >= check.count) return std::nullopt;
  return static_cast<std::uint32_t>(check.crc[static_cast<std::size_t>(number - check.first_event)]);
}

}  // namespace sculpt::logging
