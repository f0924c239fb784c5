#include "sculpt/logging/event_check.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>

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

}  // namespace sculpt::logging
