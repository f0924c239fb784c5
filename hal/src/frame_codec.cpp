#include "sculpt/hal/frame_codec.hpp"

#include <zlib.h>

#include <bit>
#include <cmath>

#include "cobs.hpp"

namespace sculpt::hal {
namespace {

constexpr std::size_t kMaxBodyBytes = kPositionsBodyBytes;
static_assert(kAnglesBodyBytes <= kMaxBodyBytes && kHapticBodyBytes <= kMaxBodyBytes);
static_assert(cobs_max_encoded_size(kMaxBodyBytes) + 1 <= kMaxFrameBytes,
              "the largest frame must fit the advertised maximum");

std::uint32_t crc32_of(std::span<const std::uint8_t> bytes) noexcept {
  // zlib's crc32 takes a uInt length; bodies are a few hundred bytes.
  return static_cast<std::uint32_t>(::crc32(::crc32(0L, Z_NULL, 0), bytes.data(), static_cast<uInt>(bytes.size())));
}

// Writes little-endian values by shifting, so the layout does not depend on the host.
class BodyWriter {
 public:
  explicit BodyWriter(std::span<std::uint8_t> body) noexcept : body_(body) {}
  void u8(std::uint8_t v) noexcept { body_[at_++] = v; }
  void u32(std::uint32_t v) noexcept {
    for (int i = 0; i < 4; ++i) body_[at_++] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void u64(std::uint64_t v) noexcept {
    for (int i = 0; i < 8; ++i) body_[at_++] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void f32(float v) noexcept { u32(std::bit_cast<std::uint32_t>(v)); }
  std::size_t size() const noexcept { return at_; }

 private:
  std::span<std::uint8_t> body_;
  std::size_t at_ = 0;
};

class BodyReader {
 public:
  explicit BodyReader(std::span<const std::uint8_t> body) noexcept : body_(body) {}
  std::uint8_t u8() noexcept { return body_[at_++]; }
  std::uint32_t u32() noexcept {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(body_[at_++]) << (8 * i);
    return v;
  }
  std::uint64_t u64() noexcept {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(body_[at_++]) << (8 * i);
    return v;
  }
  // Records a non-finite value instead of failing at once, so a reader runs straight through.
  float f32() noexcept {
    const float v = std::bit_cast<float>(u32());
    finite_ = finite_ && std::isfinite(v);
    return v;
  }
  bool all_finite() const noexcept { return finite_; }

 private:
  std::span<const std::uint8_t> body_;
  std::size_t at_ = 0;
  bool finite_ = true;
};

void write_header(BodyWriter& w, FrameType type, std::uint8_t hand, std::uint32_t sequence,
                  std::uint64_t device_time_us) noexcept {
  w.u8(kProtocolVersion);
  w.u8(static_cast<std::uint8_t>(type));
  w.u8(hand);
  w.u8(0);  // flags: none defined in version 1
  w.u32(sequence);
  w.u64(device_time_us);
}

// Appends the CRC, COBS-encodes and terminates. Returns the bytes written to out, 0 if short.
std::size_t finish_frame(std::span<std::uint8_t> body, BodyWriter& w, std::span<std::uint8_t> out) noexcept {
  const std::size_t covered = w.size();
  w.u32(crc32_of(body.first(covered)));
  const std::size_t n = cobs_encode(body.first(w.size()), out.first(out.size() - 1));
  if (n == 0) return 0;
  out[n] = 0;
  return n + 1;
}

std::size_t body_bytes_for(std::uint8_t type) noexcept {
  switch (static_cast<FrameType>(type)) {
    case FrameType::kPositions: return kPositionsBodyBytes;
    case FrameType::kAngles: return kAnglesBodyBytes;
    case FrameType::kHaptic: return kHapticBodyBytes;
  }
  return 0;
}

}  // namespace

std::size_t encode_sample_frame(const GloveSample& s, std::span<std::uint8_t> out) noexcept {
  if (out.size() < kMaxFrameBytes) return 0;
  std::array<std::uint8_t, kMaxBodyBytes> body;
  BodyWriter w(body);
  if (s.kind == SampleKind::kAngles) {
    write_header(w, FrameType::kAngles, s.hand, s.sequence, s.device_time_us);
    for (const FingerAngles& finger : s.angles) {
      for (const float a : finger) w.f32(a);
    }
    for (const float p : s.wrist.position) w.f32(p);
    for (const float q : s.wrist.orientation) w.f32(q);
  } else {
    write_header(w, FrameType::kPositions, s.hand, s.sequence, s.device_time_us);
    for (const Point3f& joint : s.joints) {
      for (const float c : joint) w.f32(c);
    }
  }
  return finish_frame(body, w, out);
}

std::size_t encode_haptic_frame(const HapticCommand& c, std::uint32_t sequence, std::uint64_t device_time_us,
                                std::span<std::uint8_t> out) noexcept {
  if (out.size() < kMaxFrameBytes) return 0;
  std::array<std::uint8_t, kMaxBodyBytes> body;
  BodyWriter w(body);
  write_header(w, FrameType::kHaptic, c.hand, sequence, device_time_us);
  w.u8(c.active_mask);
  w.u32(c.tick);
  for (const Point3f& f : c.force) {
    for (const float v : f) w.f32(v);
  }
  return finish_frame(body, w, out);
}

void FrameDecoder::reset() noexcept {
  counters_.bytes_skipped += length_;
  length_ = 0;
  skipping_ = false;
}

void FrameDecoder::overflow() noexcept {
  ++counters_.framing_errors;
  counters_.bytes_skipped += length_ + 1;  // what was buffered, and the byte that did not fit
  length_ = 0;
  skipping_ = true;
}

bool FrameDecoder::end_of_frame() noexcept {
  if (skipping_) {
    ++counters_.bytes_skipped;  // the over-long frame's delimiter
    skipping_ = false;
    return false;
  }
  const std::size_t encoded_length = length_;
  length_ = 0;
  if (encoded_length == 0) return false;  // idle fill between frames

  auto reject = [&](std::uint64_t& counter) {
    ++counter;
    counters_.bytes_skipped += encoded_length + 1;
    return false;
  };

  const std::ptrdiff_t decoded = cobs_decode(std::span(encoded_.data(), encoded_length), body_);
  if (decoded < 0) return reject(counters_.framing_errors);
  const auto body = std::span<const std::uint8_t>(body_.data(), static_cast<std::size_t>(decoded));

  // Structure before checksum: a frame cut short or of the wrong length is a framing error,
  // and crc_errors then counts well-formed frames whose contents were corrupted.
  if (body.size() < kFrameHeaderBytes + kFrameCrcBytes) return reject(counters_.framing_errors);
  if (body[0] != kProtocolVersion) return reject(counters_.framing_errors);
  const std::size_t expected = body_bytes_for(body[1]);
  if (expected == 0 || body.size() != expected) return reject(counters_.framing_errors);

  const std::size_t covered = body.size() - kFrameCrcBytes;
  BodyReader crc_reader(body.subspan(covered));
  if (crc_reader.u32() != crc32_of(body.first(covered))) return reject(counters_.crc_errors);

  BodyReader r(body);
  r.u8();  // version, checked above
  const auto type = static_cast<FrameType>(r.u8());
  const std::uint8_t hand = r.u8();
  r.u8();  // flags: none defined in version 1, ignored so a later minor use stays compatible
  const std::uint32_t sequence = r.u32();
  const std::uint64_t device_time_us = r.u64();
  if (hand >= kHands) return reject(counters_.framing_errors);

  DecodedFrame& f = frame_;
  f.sequence = sequence;
  f.device_time_us = device_time_us;
  if (type == FrameType::kHaptic) {
    f.type = DecodedFrame::Type::kHaptic;
    HapticCommand& c = f.haptic;
    c.hand = hand;
    c.active_mask = r.u8();
    c.tick = r.u32();
    for (Point3f& force : c.force) {
      for (float& v : force) v = r.f32();
    }
  } else {
    f.type = DecodedFrame::Type::kSample;
    GloveSample& s = f.sample;
    s = GloveSample{};
    s.hand = hand;
    s.sequence = sequence;
    s.device_time_us = device_time_us;
    if (type == FrameType::kPositions) {
      s.kind = SampleKind::kPositions;
      for (Point3f& joint : s.joints) {
        for (float& c : joint) c = r.f32();
      }
    } else {
      s.kind = SampleKind::kAngles;
      for (FingerAngles& finger : s.angles) {
        for (float& a : finger) a = r.f32();
      }
      for (float& p : s.wrist.position) p = r.f32();
      for (float& q : s.wrist.orientation) q = r.f32();
    }
  }
  if (!r.all_finite()) return reject(counters_.framing_errors);
  ++counters_.frames;
  return true;
}

}  // namespace sculpt::hal
