// The glove wire protocol: byte layout against docs/glove-protocol.md (checked with a CRC and
// a COBS written here independently of the codec), round trips, rejection of every kind of
// corruption, and a seeded fuzz.

#include "sculpt/hal/frame_codec.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "cobs.hpp"  // private to the library (hal/src): its unit tests live here

namespace sculpt::hal {
namespace {

using Bytes = std::vector<std::uint8_t>;

// ---- independent oracles --------------------------------------------------------------

// CRC-32/ISO-HDLC (zlib's), bit by bit: reflected polynomial 0xEDB88320, init and final xor ~0.
std::uint32_t reference_crc32(const std::uint8_t* data, std::size_t n) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// COBS as the paper describes it: split at zeros into runs, a run longer than 254 continues in
// a group with no implied zero.
Bytes reference_cobs(const Bytes& in) {
  Bytes out;
  Bytes run;
  auto flush = [&](bool final_run) {
    out.push_back(static_cast<std::uint8_t>(run.size() + 1));
    out.insert(out.end(), run.begin(), run.end());
    run.clear();
    (void)final_run;
  };
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] == 0) {
      flush(false);
      continue;
    }
    run.push_back(in[i]);
    if (run.size() == 254) {
      out.push_back(0xFF);
      out.insert(out.end(), run.begin(), run.end());
      run.clear();
      if (i + 1 == in.size()) return out;
    }
  }
  flush(true);
  return out;
}

Bytes reference_uncobs(const Bytes& in) {
  Bytes out;
  std::size_t i = 0;
  while (i < in.size()) {
    const std::uint8_t code = in[i++];
    for (int k = 1; k < code; ++k) out.push_back(in[i++]);
    if (code != 0xFF && i < in.size()) out.push_back(0);
  }
  return out;
}

// A complete frame on the wire from a body without its CRC: CRC appended, COBS, delimiter.
Bytes wire_from_body(Bytes body) {
  const std::uint32_t crc = reference_crc32(body.data(), body.size());
  for (int i = 0; i < 4; ++i) body.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  Bytes wire = reference_cobs(body);
  wire.push_back(0);
  return wire;
}

// The body of an encoded frame (delimiter stripped), CRC included.
Bytes body_of(const Bytes& wire) { return reference_uncobs(Bytes(wire.begin(), wire.end() - 1)); }

std::uint32_t le32(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b[at + i]) << (8 * i);
  return v;
}

std::uint64_t le64(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(b[at + i]) << (8 * i);
  return v;
}

float lef32(const Bytes& b, std::size_t at) { return std::bit_cast<float>(le32(b, at)); }

void put_f32(Bytes& b, std::size_t at, float v) {
  const auto u = std::bit_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(u >> (8 * i));
}

// ---- frames to test with --------------------------------------------------------------

GloveSample positions_sample(std::mt19937& rng, std::uint32_t sequence = 7) {
  std::uniform_real_distribution<float> coord(-0.3f, 0.3f);
  GloveSample s;
  s.hand = 1;
  s.kind = SampleKind::kPositions;
  s.sequence = sequence;
  s.device_time_us = 0x0123456789ABCDEFull;
  for (Point3f& j : s.joints) {
    for (float& c : j) c = coord(rng);
  }
  return s;
}

GloveSample angles_sample(std::mt19937& rng, std::uint32_t sequence = 9) {
  std::uniform_real_distribution<float> angle(-1.5f, 1.5f);
  GloveSample s;
  s.hand = 0;
  s.kind = SampleKind::kAngles;
  s.sequence = sequence;
  s.device_time_us = 123456789;
  for (FingerAngles& f : s.angles) {
    for (float& a : f) a = angle(rng);
  }
  s.wrist.position = {0.1f, -0.2f, 0.3f};
  s.wrist.orientation = {0.5f, 0.5f, -0.5f, 0.5f};
  return s;
}

HapticCommand haptic_command(std::mt19937& rng) {
  std::uniform_real_distribution<float> newton(-4.0f, 4.0f);
  HapticCommand c;
  c.hand = 1;
  c.tick = 0xA1B2C3D4u;
  c.active_mask = 0b10110;
  for (Point3f& f : c.force) {
    for (float& v : f) v = newton(rng);
  }
  return c;
}

Bytes encode(const GloveSample& s) {
  Bytes out(kMaxFrameBytes);
  out.resize(encode_sample_frame(s, out));
  return out;
}

Bytes encode(const HapticCommand& c, std::uint32_t sequence = 3, std::uint64_t time_us = 42) {
  Bytes out(kMaxFrameBytes);
  out.resize(encode_haptic_frame(c, sequence, time_us, out));
  return out;
}

// Feeds `bytes` to a fresh or given decoder, collecting the frames delivered.
std::vector<DecodedFrame> decode(FrameDecoder& decoder, const Bytes& bytes) {
  std::vector<DecodedFrame> frames;
  decoder.feed(bytes, [&](const DecodedFrame& f) { frames.push_back(f); });
  return frames;
}

std::vector<DecodedFrame> decode(const Bytes& bytes) {
  FrameDecoder decoder;
  return decode(decoder, bytes);
}

bool same_sample(const GloveSample& a, const GloveSample& b) {
  return a.hand == b.hand && a.kind == b.kind && a.sequence == b.sequence && a.device_time_us == b.device_time_us &&
         a.receive_time_ns == b.receive_time_ns && std::memcmp(&a.joints, &b.joints, sizeof a.joints) == 0 &&
         std::memcmp(&a.angles, &b.angles, sizeof a.angles) == 0 &&
         std::memcmp(&a.wrist, &b.wrist, sizeof a.wrist) == 0;
}

bool same_haptic(const HapticCommand& a, const HapticCommand& b) {
  return a.hand == b.hand && a.tick == b.tick && a.active_mask == b.active_mask &&
         std::memcmp(&a.force, &b.force, sizeof a.force) == 0;
}

bool same_frame(const DecodedFrame& a, const DecodedFrame& b) {
  if (a.type != b.type || a.sequence != b.sequence || a.device_time_us != b.device_time_us) return false;
  return a.type == DecodedFrame::Type::kSample ? same_sample(a.sample, b.sample) : same_haptic(a.haptic, b.haptic);
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

// ---- the oracles themselves -------------------------------------------------------------

TEST(FrameCodecOracle, ReferenceCrcMatchesTheCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(reference_crc32(reinterpret_cast<const std::uint8_t*>(check), 9), 0xCBF43926u);
}

// ---- COBS ------------------------------------------------------------------------------

TEST(Cobs, EncodesThePaperExamples) {
  struct Case {
    Bytes in, out;
  };
  const std::vector<Case> cases = {
      {{0x00}, {0x01, 0x01}},
      {{0x00, 0x00}, {0x01, 0x01, 0x01}},
      {{0x00, 0x11, 0x00}, {0x01, 0x02, 0x11, 0x01}},
      {{0x11, 0x22, 0x00, 0x33}, {0x03, 0x11, 0x22, 0x02, 0x33}},
      {{0x11, 0x22, 0x33, 0x44}, {0x05, 0x11, 0x22, 0x33, 0x44}},
      {{0x11, 0x00, 0x00, 0x00}, {0x02, 0x11, 0x01, 0x01, 0x01}},
      {{}, {0x01}},
  };
  for (const Case& c : cases) {
    Bytes out(cobs_max_encoded_size(c.in.size()));
    out.resize(cobs_encode(c.in, out));
    EXPECT_EQ(out, c.out);
    Bytes back(c.out.size());
    const std::ptrdiff_t n = cobs_decode(c.out, back);
    ASSERT_GE(n, 0);
    back.resize(static_cast<std::size_t>(n));
    EXPECT_EQ(back, c.in);
  }
}

TEST(Cobs, LongRunsSplitAt254AndMatchTheReference) {
  std::mt19937 rng(11);
  for (const std::size_t n : {253u, 254u, 255u, 508u, 509u, 600u}) {
    for (const bool with_zeros : {false, true}) {
      Bytes in(n);
      for (std::uint8_t& b : in) b = static_cast<std::uint8_t>(1 + rng() % 255);
      if (with_zeros) in[n / 3] = 0;
      Bytes out(cobs_max_encoded_size(n));
      out.resize(cobs_encode(in, out));
      EXPECT_EQ(out, reference_cobs(in)) << n;
      EXPECT_LE(out.size(), cobs_max_encoded_size(n));
      for (const std::uint8_t b : out) ASSERT_NE(b, 0);
      Bytes back(out.size());
      const std::ptrdiff_t m = cobs_decode(out, back);
      ASSERT_EQ(m, static_cast<std::ptrdiff_t>(n));
      back.resize(n);
      EXPECT_EQ(back, in);
    }
  }
}

TEST(Cobs, RejectsMalformedInput) {
  Bytes out(16);
  EXPECT_EQ(cobs_decode(Bytes{}, out), -1);                  // empty
  EXPECT_EQ(cobs_decode(Bytes{0x05, 0x11, 0x22}, out), -1);  // code points past the end
  EXPECT_EQ(cobs_decode(Bytes{0x03, 0x00, 0x22}, out), -1);  // a zero inside
  Bytes tiny(2);
  EXPECT_EQ(cobs_encode(Bytes{1, 2, 3}, tiny), 0u);  // output too small
}

// ---- layout ------------------------------------------------------------------------------

TEST(FrameCodec, PositionsFrameLayoutMatchesTheSpecification) {
  std::mt19937 rng(1);
  const GloveSample s = positions_sample(rng, 0xDEADBEEFu);
  const Bytes wire = encode(s);
  ASSERT_FALSE(wire.empty());
  EXPECT_EQ(wire.back(), 0);
  for (std::size_t i = 0; i + 1 < wire.size(); ++i) ASSERT_NE(wire[i], 0) << i;
  EXPECT_LE(wire.size(), kMaxFrameBytes);

  const Bytes body = body_of(wire);
  ASSERT_EQ(body.size(), 248u);
  ASSERT_EQ(body.size(), kPositionsBodyBytes);
  EXPECT_EQ(body[0], 1);  // version
  EXPECT_EQ(body[1], 1);  // type: positions
  EXPECT_EQ(body[2], 1);  // hand
  EXPECT_EQ(body[3], 0);  // flags
  EXPECT_EQ(le32(body, 4), 0xDEADBEEFu);
  EXPECT_EQ(le64(body, 8), 0x0123456789ABCDEFull);
  for (std::size_t j = 0; j < kJointPoints; ++j) {
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_EQ(lef32(body, 16 + 12 * j + 4 * c), s.joints[j][c]) << j << "," << c;
    }
  }
  EXPECT_EQ(le32(body, 244), reference_crc32(body.data(), 244));
  EXPECT_EQ(wire, wire_from_body(Bytes(body.begin(), body.end() - 4)));
}

TEST(FrameCodec, AnglesFrameLayoutMatchesTheSpecification) {
  std::mt19937 rng(2);
  const GloveSample s = angles_sample(rng);
  const Bytes body = body_of(encode(s));
  ASSERT_EQ(body.size(), 128u);
  ASSERT_EQ(body.size(), kAnglesBodyBytes);
  EXPECT_EQ(body[1], 2);
  EXPECT_EQ(body[2], 0);
  for (std::size_t f = 0; f < kFingers; ++f) {
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(lef32(body, 16 + 16 * f + 4 * k), s.angles[f][k]);
  }
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(lef32(body, 96 + 4 * c), s.wrist.position[c]);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(lef32(body, 108 + 4 * c), s.wrist.orientation[c]);
  EXPECT_EQ(le32(body, 124), reference_crc32(body.data(), 124));
}

TEST(FrameCodec, HapticFrameLayoutMatchesTheSpecification) {
  std::mt19937 rng(3);
  const HapticCommand c = haptic_command(rng);
  const Bytes body = body_of(encode(c, 77, 99));
  ASSERT_EQ(body.size(), 85u);
  ASSERT_EQ(body.size(), kHapticBodyBytes);
  EXPECT_EQ(body[1], 3);
  EXPECT_EQ(body[2], 1);
  EXPECT_EQ(le32(body, 4), 77u);
  EXPECT_EQ(le64(body, 8), 99u);
  EXPECT_EQ(body[16], 0b10110);
  EXPECT_EQ(le32(body, 17), 0xA1B2C3D4u);
  for (std::size_t f = 0; f < kFingers; ++f) {
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(lef32(body, 21 + 12 * f + 4 * k), c.force[f][k]);
  }
  EXPECT_EQ(le32(body, 81), reference_crc32(body.data(), 81));
}

TEST(FrameCodec, EncodersRefuseASmallBuffer) {
  std::mt19937 rng(4);
  Bytes small(kMaxFrameBytes - 1);
  EXPECT_EQ(encode_sample_frame(positions_sample(rng), small), 0u);
  EXPECT_EQ(encode_haptic_frame(haptic_command(rng), 0, 0, small), 0u);
}

// ---- round trips ---------------------------------------------------------------------------

TEST(FrameCodec, RoundTripsEveryFrameType) {
  std::mt19937 rng(5);
  const GloveSample p = positions_sample(rng);
  const GloveSample a = angles_sample(rng);
  const HapticCommand h = haptic_command(rng);
  const auto frames = decode(concat({encode(p), encode(a), encode(h, 1234, 5678)}));
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].type, DecodedFrame::Type::kSample);
  EXPECT_TRUE(same_sample(frames[0].sample, p));
  EXPECT_EQ(frames[0].sequence, p.sequence);
  EXPECT_EQ(frames[0].device_time_us, p.device_time_us);
  EXPECT_EQ(frames[1].type, DecodedFrame::Type::kSample);
  EXPECT_TRUE(same_sample(frames[1].sample, a));
  EXPECT_EQ(frames[2].type, DecodedFrame::Type::kHaptic);
  EXPECT_TRUE(same_haptic(frames[2].haptic, h));
  EXPECT_EQ(frames[2].sequence, 1234u);
  EXPECT_EQ(frames[2].device_time_us, 5678u);
}

TEST(FrameCodec, RoundTripsExtremeFiniteValues) {
  GloveSample s;
  s.kind = SampleKind::kPositions;
  s.sequence = 0xFFFFFFFFu;
  s.device_time_us = 0xFFFFFFFFFFFFFFFFull;
  const float extremes[] = {0.0f,
                            -0.0f,
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::lowest(),
                            std::numeric_limits<float>::denorm_min(),
                            1.0f};
  for (std::size_t j = 0; j < kJointPoints; ++j) s.joints[j] = {extremes[j % 6], extremes[(j + 1) % 6], 0.0f};
  const auto frames = decode(encode(s));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(same_sample(frames[0].sample, s));
}

// ---- rejection -----------------------------------------------------------------------------

struct Scenario {
  std::vector<DecodedFrame> frames;
  DecoderCounters counters;
};

Scenario run(const Bytes& bytes) {
  FrameDecoder d;
  Scenario s;
  s.frames = decode(d, bytes);
  s.counters = d.counters();
  return s;
}

TEST(FrameCodec, EverySingleBitFlipIsRejectedAndTheNextFrameSurvives) {
  std::mt19937 rng(6);
  const std::vector<Bytes> originals = {encode(positions_sample(rng)), encode(angles_sample(rng)),
                                        encode(haptic_command(rng))};
  const Bytes good = encode(positions_sample(rng, 100));
  const auto expected = decode(good);
  ASSERT_EQ(expected.size(), 1u);
  std::size_t flips = 0;
  for (const Bytes& original : originals) {
    for (std::size_t byte = 0; byte < original.size(); ++byte) {
      for (int bit = 0; bit < 8; ++bit) {
        Bytes corrupt = original;
        corrupt[byte] ^= static_cast<std::uint8_t>(1u << bit);
        // A delimiter after the corrupt frame bounds the damage of a flipped delimiter.
        const Scenario s = run(concat({corrupt, Bytes{0}, good}));
        ASSERT_EQ(s.frames.size(), 1u) << "byte " << byte << " bit " << bit;
        ASSERT_TRUE(same_frame(s.frames[0], expected[0])) << "byte " << byte << " bit " << bit;
        ASSERT_GE(s.counters.crc_errors + s.counters.framing_errors, 1u);
        ASSERT_GT(s.counters.bytes_skipped, 0u);
        ++flips;
      }
    }
  }
  EXPECT_EQ(flips, 8 * (originals[0].size() + originals[1].size() + originals[2].size()));
}

TEST(FrameCodec, BitFlipsInTheBodyAreCrcErrors) {
  // Flips that leave the structure intact (payload and CRC bytes, flipped before COBS) must be
  // caught by the CRC, and counted as such.
  std::mt19937 rng(7);
  const Bytes wire = encode(angles_sample(rng));
  const Bytes body = body_of(wire);
  for (std::size_t byte = kFrameHeaderBytes; byte < body.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes corrupt = body;
      corrupt[byte] ^= static_cast<std::uint8_t>(1u << bit);
      Bytes frame = reference_cobs(corrupt);
      frame.push_back(0);
      const Scenario s = run(frame);
      ASSERT_TRUE(s.frames.empty());
      ASSERT_EQ(s.counters.crc_errors, 1u) << byte << " " << bit;
      ASSERT_EQ(s.counters.framing_errors, 0u);
      ASSERT_EQ(s.counters.bytes_skipped, frame.size());
    }
  }
}

// A well-formed frame (correct CRC) whose contents break a rule: a framing error, not a CRC one.
void expect_malformed(Bytes body_without_crc, const char* what) {
  const Scenario s = run(wire_from_body(std::move(body_without_crc)));
  EXPECT_TRUE(s.frames.empty()) << what;
  EXPECT_EQ(s.counters.framing_errors, 1u) << what;
  EXPECT_EQ(s.counters.crc_errors, 0u) << what;
}

TEST(FrameCodec, RejectsWellFormedFramesThatBreakTheRules) {
  std::mt19937 rng(8);
  const Bytes positions = body_of(encode(positions_sample(rng)));
  const Bytes angles = body_of(encode(angles_sample(rng)));
  const Bytes haptic = body_of(encode(haptic_command(rng)));
  auto strip = [](const Bytes& body) { return Bytes(body.begin(), body.end() - 4); };

  // Sanity: the stripped bodies re-framed by the oracle are accepted.
  EXPECT_EQ(run(wire_from_body(strip(positions))).counters.frames, 1u);

  for (const std::uint8_t version : {0, 2, 255}) {
    Bytes b = strip(positions);
    b[0] = version;
    expect_malformed(b, "unknown version");
  }
  for (const std::uint8_t type : {0, 4, 255}) {
    Bytes b = strip(positions);
    b[1] = type;
    expect_malformed(b, "unknown type");
  }
  {
    Bytes b = strip(positions);
    b[1] = 2;  // says angles, carries positions
    expect_malformed(b, "length of another type");
  }
  {
    Bytes b = strip(angles);
    b.push_back(0x42);
    expect_malformed(b, "one byte too long");
  }
  {
    Bytes b = strip(haptic);
    b.pop_back();
    expect_malformed(b, "one byte too short");
  }
  expect_malformed(Bytes(12, 0x01), "shorter than a header");
  {
    Bytes b = strip(positions);
    b[2] = kHands;
    expect_malformed(b, "hand out of range");
  }
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  for (const float v : bad) {
    Bytes p = strip(positions);
    put_f32(p, 16 + 12 * 18 + 8, v);  // the little fingertip's z
    expect_malformed(p, "non-finite position");
    Bytes a = strip(angles);
    put_f32(a, 108, v);  // quaternion w
    expect_malformed(a, "non-finite quaternion");
    Bytes h = strip(haptic);
    put_f32(h, 21, v);  // thumb force x
    expect_malformed(h, "non-finite force");
  }
  // The encoder writes what it is given, so a NaN sample makes a frame the decoder refuses.
  GloveSample s = positions_sample(rng);
  s.joints[3][1] = std::numeric_limits<float>::quiet_NaN();
  const Scenario from_encoder = run(encode(s));
  EXPECT_TRUE(from_encoder.frames.empty());
  EXPECT_EQ(from_encoder.counters.framing_errors, 1u);
}

TEST(FrameCodec, FlagsAreIgnoredOnReceive) {
  std::mt19937 rng(9);
  Bytes b = body_of(encode(positions_sample(rng)));
  b.resize(b.size() - 4);
  b[3] = 0x80;
  EXPECT_EQ(run(wire_from_body(b)).counters.frames, 1u);
}

// ---- streams -----------------------------------------------------------------------------------

TEST(FrameCodec, ChunkingAtEverySplitPointGivesTheSameFrames) {
  std::mt19937 rng(10);
  const Bytes stream = concat({encode(positions_sample(rng)), encode(angles_sample(rng)), encode(haptic_command(rng))});
  const auto whole = decode(stream);
  ASSERT_EQ(whole.size(), 3u);
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    FrameDecoder d;
    auto frames = decode(d, Bytes(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(split)));
    const auto rest = decode(d, Bytes(stream.begin() + static_cast<std::ptrdiff_t>(split), stream.end()));
    frames.insert(frames.end(), rest.begin(), rest.end());
    ASSERT_EQ(frames.size(), 3u) << split;
    for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(same_frame(frames[i], whole[i])) << split;
    ASSERT_EQ(d.counters().framing_errors + d.counters().crc_errors, 0u);
  }
  FrameDecoder bytewise;
  std::vector<DecodedFrame> frames;
  for (const std::uint8_t b : stream) {
    bytewise.feed(std::span(&b, 1), [&](const DecodedFrame& f) { frames.push_back(f); });
  }
  ASSERT_EQ(frames.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(same_frame(frames[i], whole[i]));
}

TEST(FrameCodec, ResynchronisesAfterGarbageBetweenFrames) {
  std::mt19937 rng(12);
  Bytes stream;
  std::vector<DecodedFrame> sent;
  for (int i = 0; i < 50; ++i) {
    const Bytes frame = encode(positions_sample(rng, static_cast<std::uint32_t>(i)));
    sent.push_back(decode(frame).at(0));
    stream.insert(stream.end(), frame.begin(), frame.end());
    const std::size_t garbage = rng() % 40;
    for (std::size_t k = 0; k < garbage; ++k) stream.push_back(static_cast<std::uint8_t>(rng()));
    stream.push_back(0);  // garbage may or may not end in one; the next frame must start clean
  }
  const Scenario s = run(stream);
  ASSERT_EQ(s.frames.size(), sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) EXPECT_TRUE(same_frame(s.frames[i], sent[i]));
  EXPECT_EQ(s.counters.frames, sent.size());
  EXPECT_GT(s.counters.framing_errors, 0u);
}

TEST(FrameCodec, TruncatedFramesAreFramingErrors) {
  std::mt19937 rng(13);
  const Bytes full = encode(positions_sample(rng));
  const Bytes next = encode(angles_sample(rng));
  for (std::size_t keep = 1; keep + 1 < full.size(); ++keep) {
    Bytes stream(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(keep));
    stream.push_back(0);
    stream.insert(stream.end(), next.begin(), next.end());
    const Scenario s = run(stream);
    ASSERT_EQ(s.frames.size(), 1u) << keep;
    ASSERT_EQ(s.frames[0].sample.kind, SampleKind::kAngles);
    ASSERT_EQ(s.counters.framing_errors, 1u) << keep;
    ASSERT_EQ(s.counters.crc_errors, 0u) << keep;
    ASSERT_EQ(s.counters.bytes_skipped, keep + 1);
  }
}

TEST(FrameCodec, OverLongFramesAreDroppedUpToTheNextDelimiter) {
  std::mt19937 rng(14);
  const Bytes good = encode(positions_sample(rng));
  for (const std::size_t length : {kMaxFrameBytes - 1, kMaxFrameBytes, kMaxFrameBytes + 1, 3000ul}) {
    Bytes stream(length, 0x5A);
    stream.push_back(0);
    stream.insert(stream.end(), good.begin(), good.end());
    const Scenario s = run(stream);
    ASSERT_EQ(s.frames.size(), 1u) << length;
    EXPECT_EQ(s.counters.framing_errors, 1u) << length;
    EXPECT_EQ(s.counters.bytes_skipped, length + 1) << length;
  }
}

TEST(FrameCodec, EmptyFramesAreIdleFillNotErrors) {
  std::mt19937 rng(15);
  const Scenario s =
      run(concat({Bytes(5, 0), encode(haptic_command(rng)), Bytes(3, 0), encode(angles_sample(rng)), Bytes(1, 0)}));
  EXPECT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.counters.frames, 2u);
  EXPECT_EQ(s.counters.framing_errors, 0u);
  EXPECT_EQ(s.counters.crc_errors, 0u);
  EXPECT_EQ(s.counters.bytes_skipped, 0u);
}

TEST(FrameCodec, CountsAScriptedStreamExactly) {
  std::mt19937 rng(16);
  Bytes bad_crc = body_of(encode(positions_sample(rng, 3)));
  bad_crc[100] ^= 0x10;
  Bytes bad_crc_wire = reference_cobs(bad_crc);
  bad_crc_wire.push_back(0);
  const Bytes garbage = {0x13, 0x37, 0xC0, 0xFF, 0xEE, 0x00};
  const Scenario s =
      run(concat({encode(positions_sample(rng, 0)), encode(positions_sample(rng, 1)), encode(angles_sample(rng, 2)),
                  garbage, bad_crc_wire, encode(haptic_command(rng)), encode(positions_sample(rng, 4))}));
  EXPECT_EQ(s.counters.frames, 5u);
  EXPECT_EQ(s.counters.crc_errors, 1u);
  EXPECT_EQ(s.counters.framing_errors, 1u);
  EXPECT_EQ(s.counters.bytes_skipped, garbage.size() + bad_crc_wire.size());
  ASSERT_EQ(s.frames.size(), 5u);
  EXPECT_EQ(s.frames[3].type, DecodedFrame::Type::kHaptic);
  EXPECT_EQ(s.frames[4].sequence, 4u);
}

TEST(FrameCodec, ResetDropsAPartialFrameWithoutAnError) {
  std::mt19937 rng(17);
  const Bytes frame = encode(positions_sample(rng));
  FrameDecoder d;
  EXPECT_TRUE(decode(d, Bytes(frame.begin(), frame.begin() + 100)).empty());
  d.reset();
  EXPECT_EQ(decode(d, frame).size(), 1u);
  EXPECT_EQ(d.counters().framing_errors, 0u);
  EXPECT_EQ(d.counters().bytes_skipped, 100u);
}

// ---- fuzz ----------------------------------------------------------------------------------------

TEST(FrameCodecFuzz, RandomStreamsNeverCrashAndCountConsistently) {
  std::mt19937 rng(20240611);
  std::vector<Bytes> pool;
  for (int i = 0; i < 8; ++i) {
    pool.push_back(encode(positions_sample(rng, static_cast<std::uint32_t>(i))));
    pool.push_back(encode(angles_sample(rng, static_cast<std::uint32_t>(i))));
    pool.push_back(encode(haptic_command(rng), static_cast<std::uint32_t>(i)));
  }
  std::vector<std::vector<DecodedFrame>> pool_frames;
  for (const Bytes& p : pool) pool_frames.push_back(decode(p));

  for (int iteration = 0; iteration < 3000; ++iteration) {
    // Random bytes, whole frames, frame fragments and mutated frames, in random order.
    Bytes stream;
    const int pieces = 1 + static_cast<int>(rng() % 12);
    for (int p = 0; p < pieces; ++p) {
      const Bytes& frame = pool[rng() % pool.size()];
      switch (rng() % 5) {
        case 0: {
          const std::size_t n = rng() % 700;
          for (std::size_t k = 0; k < n; ++k) stream.push_back(static_cast<std::uint8_t>(rng()));
          break;
        }
        case 1: stream.insert(stream.end(), frame.begin(), frame.end()); break;
        case 2:
          stream.insert(stream.end(), frame.begin(), frame.begin() + static_cast<std::ptrdiff_t>(rng() % frame.size()));
          break;
        default: {
          Bytes m = frame;
          const int edits = 1 + static_cast<int>(rng() % 4);
          for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % m.size();
            switch (rng() % 3) {
              case 0: m[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8)); break;
              case 1: m.erase(m.begin() + static_cast<std::ptrdiff_t>(at)); break;
              default: m.insert(m.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint8_t>(rng()));
            }
            if (m.empty()) m.push_back(0);
          }
          stream.insert(stream.end(), m.begin(), m.end());
        }
      }
    }
    // The same stream whole and in random chunks must decode identically.
    const Scenario whole = run(stream);
    FrameDecoder chunked;
    std::vector<DecodedFrame> chunk_frames;
    for (std::size_t at = 0; at < stream.size();) {
      const std::size_t n = std::min<std::size_t>(stream.size() - at, 1 + rng() % 300);
      chunked.feed(std::span(stream.data() + at, n), [&](const DecodedFrame& f) { chunk_frames.push_back(f); });
      at += n;
    }
    ASSERT_EQ(chunk_frames.size(), whole.frames.size()) << iteration;
    const DecoderCounters& c = chunked.counters();
    ASSERT_EQ(c.frames, whole.counters.frames);
    ASSERT_EQ(c.crc_errors, whole.counters.crc_errors);
    ASSERT_EQ(c.framing_errors, whole.counters.framing_errors);
    ASSERT_EQ(c.bytes_skipped, whole.counters.bytes_skipped);

    // Each delivered frame is one that was sent (the CRC lets nothing else through).
    ASSERT_EQ(c.frames, whole.frames.size());
    for (const DecodedFrame& f : whole.frames) {
      bool known = false;
      for (const auto& pf : pool_frames) known = known || same_frame(f, pf[0]);
      ASSERT_TRUE(known) << iteration;
    }
    // Every event ends at a delimiter or at an overflow; skipped bytes come from the stream.
    std::uint64_t zeros = 0;
    for (const std::uint8_t b : stream) zeros += b == 0;
    ASSERT_LE(c.frames + c.crc_errors + c.framing_errors, zeros + stream.size() / (kMaxFrameBytes - 1));
    ASSERT_LE(c.bytes_skipped, stream.size());
  }
}

}  // namespace
}  // namespace sculpt::hal
