#pragma once
// Consistent Overhead Byte Stuffing (Cheshire and Baker, 1999): rewrites a byte string so it
// contains no 0x00, which then marks frame boundaries on a byte stream. Every 0x00 becomes a
// code byte giving the distance to the next one, so a receiver that lands in the middle of a
// stream resynchronises at the next 0x00. Overhead: one byte, plus one per 254 bytes.

#include <cstddef>
#include <cstdint>
#include <span>

namespace sculpt::hal {

/// Largest encoding of `n` input bytes (without the 0x00 delimiter).
constexpr std::size_t cobs_max_encoded_size(std::size_t n) noexcept { return n + n / 254 + 1; }

/// Encodes `in` into `out` (no delimiter). Returns the bytes written, or 0 when `out` is
/// smaller than cobs_max_encoded_size(in.size()).
std::size_t cobs_encode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) noexcept;

/// Decodes one frame's bytes (delimiter already removed) into `out`, which needs in.size()
/// bytes. Returns the decoded length, or -1 when `in` is not valid COBS: it holds a 0x00, a
/// code byte points past its end, or it is empty.
std::ptrdiff_t cobs_decode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) noexcept;

}  // namespace sculpt::hal
