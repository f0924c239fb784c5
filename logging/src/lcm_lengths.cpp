#include "sculpt/logging/lcm_lengths.hpp"

#include <cstddef>

namespace sculpt::logging {
namespace {

// Reads a payload front to back as LCM encodes it (big-endian), past the 8-byte fingerprint.
// Each step returns false to stop the walk: with problem() set for a length that does not fit,
// or empty when the payload ends first (decode() then reports it as too short).
class PayloadWalk {
 public:
  explicit PayloadWalk(std::span<const std::uint8_t> payload) : payload_(payload) {}

  /// Steps over `bytes` of fixed-size fields.
  bool skip(std::size_t bytes) {
    if (bytes > left()) return false;
    at_ += bytes;
    return true;
  }
  /// An array's element count, then its elements.
  bool array(const char* name, std::size_t element_bytes) {
    std::int32_t count = 0;
    if (!int32(count)) return false;
    if (count < 0 || static_cast<std::size_t>(count) > left() / element_bytes) {
      return bad(name, "count", count,
                 count < 0 ? "is negative"
                           : "needs " + std::to_string(static_cast<std::size_t>(count) * element_bytes) + " bytes");
    }
    at_ += static_cast<std::size_t>(count) * element_bytes;
    return true;
  }
  /// A string: its length counts its terminating NUL, so it is at least 1.
  bool string(const char* name) {
    std::int32_t length = 0;
    if (!int32(length)) return false;
    if (length < 1 || static_cast<std::size_t>(length) > left()) {
      return bad(name, "length", length,
                 length < 1 ? "is below 1 (it counts the NUL)" : "needs " + std::to_string(length) + " bytes");
    }
    at_ += static_cast<std::size_t>(length);
    return true;
  }
  const std::string& problem() const { return problem_; }

 private:
  std::size_t left() const { return at_ < payload_.size() ? payload_.size() - at_ : 0; }
  bool int32(std::int32_t& out) {
    if (left() < 4) return false;
    std::uint32_t bits = 0;
    for (std::size_t k = 0; k < 4; ++k) bits = (bits << 8) | payload_[at_ + k];
    at_ += 4;
    out = static_cast<std::int32_t>(bits);
    return true;
  }
  bool bad(const char* field, const char* what, std::int32_t value, const std::string& reason) {
    problem_ = std::string(field) + "'s " + what + " " + std::to_string(value) + " at payload byte " +
               std::to_string(at_ - 4) + " " + reason + " (" + std::to_string(left()) + " of the payload's " +
               std::to_string(payload_.size()) + " bytes are left)";
    return false;
  }

  std::span<const std::uint8_t> payload_;
  std::size_t at_ = 8;  // past the fingerprint, which decode() has checked
  std::string problem_;
};

}  // namespace

std::string payload_lengths_problem(const sculpt_lcm::log_check_t&, std::span<const std::uint8_t> payload) {
  PayloadWalk walk(payload);
  // int64 first_event; int32 count; int32 crc[count]
  if (walk.skip(8) && walk.array("crc", 4)) return {};
  return walk.problem();
}

std::string payload_lengths_problem(const sculpt_lcm::session_header_t&, std::span<const std::uint8_t> payload) {
  PayloadWalk walk(payload);
  // int64 utime; int32 schema; string version, scene_path, scene_text; then fixed-size fields
  if (walk.skip(8 + 4) && walk.string("version") && walk.string("scene_path") && walk.string("scene_text")) return {};
  return walk.problem();
}

}  // namespace sculpt::logging
