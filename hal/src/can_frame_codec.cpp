#include "sculpt/hal/can_frame_codec.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace sculpt::hal {
namespace {

constexpr std::size_t kHeaderBytes = 1;
constexpr std::size_t kCrcBytes = 4;
constexpr unsigned kIndexMask = 0x3F;                 // header bits 5..0: segment index
constexpr unsigned kSeqShift = 6;                     // header bits 7..6: low bits of the sequence or tick
constexpr std::size_t kSampleFixedBytes = 1 + 4 + 8;  // kind, sequence, device time
constexpr std::size_t kPositionFloats = kJointPoints * 3;
constexpr std::size_t kAngleFloats = kFingers * 4 + 3 + 4;  // finger angles, wrist position, quaternion
constexpr std::size_t kHapticPayload = kCanHapticMessageSize - kCrcBytes;

constexpr std::array<std::uint32_t, 256> make_crc_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) ? (0xEDB88320U ^ (c >> 1)) : (c >> 1);
    table[i] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = make_crc_table();

std::size_t chunk_size(bool fd) noexcept { return (fd ? kCanFdLen : kCanClassicLen) - kHeaderBytes; }

// Little-endian writer and reader over a fixed buffer; positions are checked by the callers'
// fixed layouts, not here.
struct Writer {
  std::uint8_t* p;
  void u8(std::uint8_t v) noexcept { *p++ = v; }
  void u32(std::uint32_t v) noexcept {
    for (int i = 0; i < 4; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void u64(std::uint64_t v) noexcept {
    for (int i = 0; i < 8; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
  }
  void f32(float v) noexcept { u32(std::bit_cast<std::uint32_t>(v)); }
};

struct Reader {
  const std::uint8_t* p;
  std::uint8_t u8() noexcept { return *p++; }
  std::uint32_t u32() noexcept {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(*p++) << (8 * i);
    return v;
  }
  std::uint64_t u64() noexcept {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(*p++) << (8 * i);
    return v;
  }
  float f32() noexcept { return std::bit_cast<float>(u32()); }
};

bool ids_fit(std::uint32_t base_id) noexcept { return base_id <= kCanMaxExtendedId - kCanIdSpan; }

// Splits message[0..size) into frames: header byte, then the chunk; the last frame is as
// short as its bytes allow (FD: padded with zeros to a valid length).
std::size_t split(const std::uint8_t* message, std::size_t size, std::uint32_t first_id, bool sample_ids, unsigned seq,
                  bool fd, std::span<CanFrame> out) noexcept {
  const std::size_t chunk = chunk_size(fd);
  const std::size_t count = can_segment_count(size, fd);
  if (out.size() < count) return 0;
  for (std::size_t k = 0; k < count; ++k) {
    CanFrame& f = out[k];
    const std::size_t offset = k * chunk;
    const std::size_t n = std::min(chunk, size - offset);
    f = CanFrame{};
    f.id = first_id + (sample_ids ? static_cast<std::uint32_t>(k) : 0U);
    f.fd = fd;
    f.data[0] = static_cast<std::uint8_t>(((seq & 3U) << kSeqShift) | (k & kIndexMask));
    std::memcpy(f.data.data() + kHeaderBytes, message + offset, n);
    f.len = fd ? can_fd_round_up(kHeaderBytes + n) : static_cast<std::uint8_t>(kHeaderBytes + n);
  }
  return count;
}

void append_crc(std::uint8_t* message, std::size_t payload) noexcept {
  Writer w{message + payload};
  w.u32(can_crc32({message, payload}));
}

}  // namespace

std::uint32_t can_crc32(std::span<const std::uint8_t> bytes) noexcept {
  std::uint32_t c = 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) c = kCrcTable[(c ^ b) & 0xFFU] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
}

std::uint8_t can_fd_round_up(std::size_t n) noexcept {
  constexpr std::array<std::uint8_t, 7> kLonger = {12, 16, 20, 24, 32, 48, 64};
  if (n <= 8) return static_cast<std::uint8_t>(n);
  for (const std::uint8_t l : kLonger)
    if (n <= l) return l;
  return 64;
}

std::size_t can_sample_message_size(SampleKind kind) noexcept {
  switch (kind) {
    case SampleKind::kPositions: return kSampleFixedBytes + kPositionFloats * 4 + kCrcBytes;
    case SampleKind::kAngles: return kSampleFixedBytes + kAngleFloats * 4 + kCrcBytes;
  }
  return 0;
}

std::size_t can_segment_count(std::size_t message_size, bool fd) noexcept {
  const std::size_t chunk = chunk_size(fd);
  return (message_size + chunk - 1) / chunk;
}

std::size_t encode_sample(const GloveSample& sample, std::uint32_t base_id, bool fd, std::span<CanFrame> out) noexcept {
  const std::size_t size = can_sample_message_size(sample.kind);
  if (size == 0 || sample.hand >= kHands || !ids_fit(base_id)) return 0;
  std::array<std::uint8_t, kCanMaxMessage> message{};
  Writer w{message.data()};
  w.u8(static_cast<std::uint8_t>(sample.kind));
  w.u32(sample.sequence);
  w.u64(sample.device_time_us);
  if (sample.kind == SampleKind::kPositions) {
    for (const Point3f& p : sample.joints)
      for (const float c : p) w.f32(c);
  } else {
    for (const FingerAngles& a : sample.angles)
      for (const float c : a) w.f32(c);
    for (const float c : sample.wrist.position) w.f32(c);
    for (const float c : sample.wrist.orientation) w.f32(c);
  }
  append_crc(message.data(), size - kCrcBytes);
  return split(message.data(), size, base_id + sample.hand * kCanHandStride, true, sample.sequence, fd, out);
}

std::size_t encode_haptic(const HapticCommand& command, std::uint32_t base_id, bool fd,
                          std::span<CanFrame> out) noexcept {
  if (command.hand >= kHands || !ids_fit(base_id)) return 0;
  std::array<std::uint8_t, kCanMaxMessage> message{};
  Writer w{message.data()};
  w.u8(command.active_mask);
  w.u32(command.tick);
  for (const Point3f& f : command.force)
    for (const float c : f) w.f32(c);
  append_crc(message.data(), kHapticPayload);
  return split(message.data(), kCanHapticMessageSize, base_id + kCanHapticOffset + command.hand, false, command.tick,
               fd, out);
}

// --- reassembly ---------------------------------------------------------------------------

CanReassembler::CanReassembler(std::uint32_t first_id, bool sample_ids, bool fd) noexcept
    : first_id_(first_id), sample_ids_(sample_ids), fd_(fd), chunk_(chunk_size(fd)) {}

void CanReassembler::reset() noexcept {
  state_ = State::kIdle;
  message_size_ = 0;
  next_index_ = 0;
  have_last_ = false;
}

CanFeedResult CanReassembler::broken(CanFeedResult why) noexcept {
  if (why == CanFeedResult::kCrcError)
    ++counters_.crc_errors;
  else
    ++counters_.framing_errors;
  state_ = State::kDiscarding;
  have_last_ = false;
  return why;
}

bool CanReassembler::is_duplicate(const CanFrame& frame, unsigned index, unsigned seq) const noexcept {
  if (!have_last_ || index != last_index_ || seq != seq_bits_) return false;
  const std::size_t offset = index * chunk_;
  const std::size_t n = std::min(chunk_, message_size_ - offset);
  if (frame.len < kHeaderBytes + n) return false;
  return std::memcmp(frame.data.data() + kHeaderBytes, buffer_.data() + offset, n) == 0;
}

CanFeedResult CanReassembler::feed(const CanFrame& frame) noexcept {
  const bool ours =
      sample_ids_ ? (frame.id >= first_id_ && frame.id - first_id_ < kCanHandStride) : frame.id == first_id_;
  if (!ours) return CanFeedResult::kIgnored;
  ++counters_.frames;

  const std::size_t max_len = fd_ ? kCanFdLen : kCanClassicLen;
  if (frame.fd != fd_ || frame.len < kHeaderBytes + 1 || frame.len > max_len)
    return broken(CanFeedResult::kFramingError);
  const unsigned index = frame.data[0] & kIndexMask;
  const unsigned seq = static_cast<unsigned>(frame.data[0]) >> kSeqShift;
  if (sample_ids_ && frame.id - first_id_ != index) return broken(CanFeedResult::kFramingError);

  if (is_duplicate(frame, index, seq)) {
    ++counters_.duplicates;
    return CanFeedResult::kDuplicate;
  }

  if (index == 0) {
    // A new message. One that was still open lost its tail: that is its framing error.
    if (state_ == State::kAssembling) ++counters_.framing_errors;
    const std::size_t size =
        sample_ids_ ? can_sample_message_size(static_cast<SampleKind>(frame.data[1])) : kCanHapticMessageSize;
    if (size == 0) return broken(CanFeedResult::kFramingError);
    state_ = State::kAssembling;
    message_size_ = size;
    seq_bits_ = seq;
    next_index_ = 0;
  } else if (state_ == State::kDiscarding) {
    ++counters_.discarded;
    return CanFeedResult::kDiscarded;
  } else if (state_ == State::kIdle || index != next_index_ || seq != seq_bits_) {
    return broken(CanFeedResult::kFramingError);
  }

  const std::size_t offset = index * chunk_;
  if (offset >= message_size_) return broken(CanFeedResult::kFramingError);
  const std::size_t n = std::min(chunk_, message_size_ - offset);
  if (frame.len < kHeaderBytes + n) return broken(CanFeedResult::kFramingError);
  std::memcpy(buffer_.data() + offset, frame.data.data() + kHeaderBytes, n);
  have_last_ = true;
  last_index_ = index;
  ++next_index_;
  if (offset + n < message_size_) return CanFeedResult::kPending;

  state_ = State::kIdle;
  const std::size_t payload = message_size_ - kCrcBytes;
  Reader r{buffer_.data() + payload};
  if (r.u32() != can_crc32({buffer_.data(), payload})) {
    const CanFeedResult result = broken(CanFeedResult::kCrcError);
    state_ = State::kIdle;  // nothing left of this message to discard
    return result;
  }
  payload_size_ = payload;
  ++counters_.messages;
  return CanFeedResult::kComplete;
}

// --- decoders -----------------------------------------------------------------------------

CanSampleDecoder::CanSampleDecoder(std::uint32_t base_id, std::uint8_t hand, bool fd) noexcept
    : hand_(hand), reassembler_(base_id + hand * kCanHandStride, true, fd) {}

void CanSampleDecoder::reset() noexcept {
  reassembler_.reset();
  have_sequence_ = false;
}

CanFeedResult CanSampleDecoder::feed(const CanFrame& frame, GloveSample& out) noexcept {
  const CanFeedResult result = reassembler_.feed(frame);
  if (result != CanFeedResult::kComplete) return result;
  Reader r{reassembler_.message().data()};
  GloveSample s;
  s.hand = hand_;
  s.kind = static_cast<SampleKind>(r.u8());
  s.sequence = r.u32();
  s.device_time_us = r.u64();
  bool finite = true;
  const auto take = [&](float& v) {
    v = r.f32();
    finite = finite && std::isfinite(v);
  };
  if (s.kind == SampleKind::kPositions) {
    for (Point3f& p : s.joints)
      for (float& c : p) take(c);
  } else {
    for (FingerAngles& a : s.angles)
      for (float& c : a) take(c);
    for (float& c : s.wrist.position) take(c);
    for (float& c : s.wrist.orientation) take(c);
  }
  CanDecoderCounters& c = reassembler_.counters();
  if (!finite) {
    // The device sent it so (the CRC matched), but a NaN must never reach the deformer.
    --c.messages;
    ++c.framing_errors;
    return CanFeedResult::kFramingError;
  }
  if (have_sequence_ && s.sequence != next_sequence_) {
    const std::uint32_t missing = s.sequence - next_sequence_;
    // A jump backwards (the device restarted its counter) is not a gap.
    if (missing < 0x80000000U) c.sequence_gaps += missing;
  }
  have_sequence_ = true;
  next_sequence_ = s.sequence + 1;
  out = s;
  return CanFeedResult::kComplete;
}

CanHapticDecoder::CanHapticDecoder(std::uint32_t base_id, std::uint8_t hand, bool fd) noexcept
    : hand_(hand), reassembler_(base_id + kCanHapticOffset + hand, false, fd) {}

CanFeedResult CanHapticDecoder::feed(const CanFrame& frame, HapticCommand& out) noexcept {
  const CanFeedResult result = reassembler_.feed(frame);
  if (result != CanFeedResult::kComplete) return result;
  Reader r{reassembler_.message().data()};
  HapticCommand c;
  c.hand = hand_;
  c.active_mask = r.u8();
  c.tick = r.u32();
  for (Point3f& f : c.force)
    for (float& v : f) v = r.f32();
  out = c;
  return CanFeedResult::kComplete;
}

}  // namespace sculpt::hal
