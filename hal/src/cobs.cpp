#include "cobs.hpp"

namespace sculpt::hal {

std::size_t cobs_encode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) noexcept {
  if (out.size() < cobs_max_encoded_size(in.size())) return 0;
  std::size_t code_at = 0;  // where the current group's code byte goes, filled in when it closes
  std::size_t o = 1;
  std::uint8_t code = 1;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const std::uint8_t b = in[i];
    if (b == 0) {
      out[code_at] = code;
      code_at = o++;
      code = 1;
      continue;
    }
    out[o++] = b;
    if (++code == 0xFF) {
      // A full group of 254 data bytes carries no implied zero. The next group is opened only
      // if input remains, which keeps the encoding canonical (no trailing empty group).
      out[code_at] = code;
      if (i + 1 == in.size()) return o;
      code_at = o++;
      code = 1;
    }
  }
  out[code_at] = code;
  return o;
}

std::ptrdiff_t cobs_decode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) noexcept {
  if (in.empty() || out.size() < in.size()) return -1;
  std::size_t i = 0;
  std::size_t o = 0;
  while (i < in.size()) {
    const std::uint8_t code = in[i++];
    if (code == 0) return -1;
    const std::size_t data = code - 1u;
    if (data > in.size() - i) return -1;
    for (std::size_t k = 0; k < data; ++k) {
      const std::uint8_t b = in[i++];
      if (b == 0) return -1;
      out[o++] = b;
    }
    // The implied zero follows every group except a full one and the last one.
    if (code != 0xFF && i < in.size()) out[o++] = 0;
  }
  return static_cast<std::ptrdiff_t>(o);
}

}  // namespace sculpt::hal
