// The CAN codec: CRC against the standard check value, round trips over classic CAN and
// CAN FD, every segment order, loss and duplicate, single-bit corruption, and seeded fuzz.
// The decoder must never deliver a sample that differs from what was sent.

#include "sculpt/hal/can_frame_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string_view>
#include <vector>

namespace sculpt::hal {
namespace {

constexpr std::uint32_t kBase = 0x100;

GloveSample random_sample(std::mt19937_64& rng, SampleKind kind, std::uint8_t hand, std::uint32_t sequence) {
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  GloveSample s;
  s.hand = hand;
  s.kind = kind;
  s.sequence = sequence;
  s.device_time_us = rng();
  if (kind == SampleKind::kPositions) {
    for (auto& p : s.joints)
      for (float& c : p) c = u(rng);
  } else {
    for (auto& a : s.angles)
      for (float& c : a) c = u(rng);
    for (float& c : s.wrist.position) c = u(rng);
    for (float& c : s.wrist.orientation) c = u(rng);
  }
  return s;
}

bool same(const GloveSample& a, const GloveSample& b) {
  return a.hand == b.hand && a.kind == b.kind && a.sequence == b.sequence && a.device_time_us == b.device_time_us &&
         std::memcmp(&a.joints, &b.joints, sizeof a.joints) == 0 &&
         std::memcmp(&a.angles, &b.angles, sizeof a.angles) == 0 &&
         std::memcmp(&a.wrist, &b.wrist, sizeof a.wrist) == 0;
}

std::vector<CanFrame> encode(const GloveSample& s, bool fd) {
  std::vector<CanFrame> frames(kCanMaxSampleFrames);
  frames.resize(encode_sample(s, kBase, fd, frames));
  return frames;
}

struct Mode {
  bool fd;
  SampleKind kind;
  std::size_t segments;
};
constexpr Mode kModes[] = {{false, SampleKind::kPositions, 35},
                           {false, SampleKind::kAngles, 18},
                           {true, SampleKind::kPositions, 4},
                           {true, SampleKind::kAngles, 2}};

TEST(CanCrc32, MatchesTheStandardCheckValue) {
  constexpr std::string_view kCheck = "123456789";
  const auto* p = reinterpret_cast<const std::uint8_t*>(kCheck.data());
  EXPECT_EQ(can_crc32({p, kCheck.size()}), 0xCBF43926U);
  EXPECT_EQ(can_crc32({}), 0x00000000U);
  const std::uint8_t zeros[4] = {};
  EXPECT_EQ(can_crc32(zeros), 0x2144DF1CU);
}

TEST(CanFrameCodec, SizesAndLengths) {
  EXPECT_EQ(can_sample_message_size(SampleKind::kPositions), 1 + 4 + 8 + 57 * 4 + 4u);
  EXPECT_EQ(can_sample_message_size(SampleKind::kAngles), 1 + 4 + 8 + 27 * 4 + 4u);
  EXPECT_EQ(can_sample_message_size(static_cast<SampleKind>(9)), 0u);
  for (const Mode& m : kModes) EXPECT_EQ(can_segment_count(can_sample_message_size(m.kind), m.fd), m.segments);
  EXPECT_EQ(can_segment_count(kCanHapticMessageSize, false), kCanMaxHapticFrames);
  EXPECT_EQ(can_segment_count(kCanHapticMessageSize, true), 2u);
  const std::uint8_t want[65] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  12, 12, 12, 12, 16, 16, 16, 16, 20, 20, 20, 20, 24,
                                 24, 24, 24, 32, 32, 32, 32, 32, 32, 32, 32, 48, 48, 48, 48, 48, 48, 48, 48, 48, 48, 48,
                                 48, 48, 48, 48, 48, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64, 64};
  for (std::size_t n = 0; n <= 64; ++n) EXPECT_EQ(can_fd_round_up(n), want[n]) << n;
}

TEST(CanFrameCodec, FramesFollowTheDocumentedLayout) {
  std::mt19937_64 rng(1);
  const GloveSample s = random_sample(rng, SampleKind::kPositions, 1, 0x12345677);
  const auto classic = encode(s, false);
  ASSERT_EQ(classic.size(), 35u);
  for (std::size_t k = 0; k < classic.size(); ++k) {
    EXPECT_EQ(classic[k].id, kBase + 0x40 + k);
    EXPECT_FALSE(classic[k].fd);
    EXPECT_EQ(classic[k].data[0], (0x3u << 6) | k);  // sequence & 3 = 3, segment index
    EXPECT_EQ(classic[k].len, k + 1 < classic.size() ? 8 : 1 + (245 - 34 * 7));
  }
  // Segment 0: kind, then the sequence little-endian.
  EXPECT_EQ(classic[0].data[1], 1);
  EXPECT_EQ(classic[0].data[2], 0x77);
  EXPECT_EQ(classic[0].data[5], 0x12);
  const auto fd = encode(s, true);
  ASSERT_EQ(fd.size(), 4u);
  EXPECT_EQ(fd[3].len, 64);  // 1 + 245 - 3 * 63 = 57 bytes, padded to 64
  EXPECT_TRUE(fd[3].fd);
  // The last four message bytes are the CRC of the rest.
  std::vector<std::uint8_t> message;
  for (const auto& f : fd) message.insert(message.end(), f.data.begin() + 1, f.data.begin() + 64);
  message.resize(245);
  const std::uint32_t crc = can_crc32({message.data(), 241});
  EXPECT_EQ(
      message[241] | (message[242] << 8) | (message[243] << 16) | (static_cast<std::uint32_t>(message[244]) << 24),
      crc);
}

TEST(CanFrameCodec, RoundTripsEveryModeAndHand) {
  std::mt19937_64 rng(11);
  for (const Mode& m : kModes) {
    for (std::uint8_t hand = 0; hand < kHands; ++hand) {
      CanSampleDecoder decoder(kBase, hand, m.fd);
      CanSampleDecoder other(kBase, static_cast<std::uint8_t>(1 - hand), m.fd);
      for (std::uint32_t seq = 0; seq < 20; ++seq) {
        const GloveSample s = random_sample(rng, m.kind, hand, seq);
        const auto frames = encode(s, m.fd);
        ASSERT_EQ(frames.size(), m.segments);
        GloveSample out;
        for (std::size_t k = 0; k < frames.size(); ++k) {
          const CanFeedResult r = decoder.feed(frames[k], out);
          EXPECT_EQ(r, k + 1 == frames.size() ? CanFeedResult::kComplete : CanFeedResult::kPending);
          EXPECT_EQ(other.feed(frames[k], out), CanFeedResult::kIgnored);
        }
        EXPECT_TRUE(same(out, s));
      }
      EXPECT_EQ(decoder.counters().messages, 20u);
      EXPECT_EQ(decoder.counters().framing_errors + decoder.counters().crc_errors, 0u);
      EXPECT_EQ(decoder.counters().sequence_gaps, 0u);
    }
  }
}

TEST(CanFrameCodec, HapticRoundTripsAndUsesOneIdPerHand) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> u(-10, 10);
  for (const bool fd : {false, true}) {
    HapticCommand c;
    c.hand = 1;
    c.tick = 0xDEADBEEF;
    c.active_mask = 0x15;
    for (auto& f : c.force)
      for (float& v : f) v = u(rng);
    std::array<CanFrame, kCanMaxHapticFrames> frames;
    const std::size_t n = encode_haptic(c, kBase, fd, frames);
    ASSERT_EQ(n, fd ? 2u : 10u);
    CanHapticDecoder decoder(kBase, 1, fd);
    CanHapticDecoder hand0(kBase, 0, fd);
    HapticCommand out;
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(frames[k].id, kBase + 0x81);
      EXPECT_EQ(hand0.feed(frames[k], out), CanFeedResult::kIgnored);
      EXPECT_EQ(decoder.feed(frames[k], out), k + 1 == n ? CanFeedResult::kComplete : CanFeedResult::kPending);
    }
    EXPECT_EQ(out.hand, 1);
    EXPECT_EQ(out.tick, c.tick);
    EXPECT_EQ(out.active_mask, c.active_mask);
    EXPECT_EQ(out.force, c.force);
  }
}

// Feeds frames in `order` then a fresh good sample, which must always decode: the decoder
// recovers from whatever came before.
void expect_recovers(CanSampleDecoder& d, std::mt19937_64& rng, const Mode& m, std::uint32_t seq) {
  const GloveSample good = random_sample(rng, m.kind, 0, seq);
  GloveSample out;
  CanFeedResult r = CanFeedResult::kPending;
  for (const auto& f : encode(good, m.fd)) r = d.feed(f, out);
  ASSERT_EQ(r, CanFeedResult::kComplete);
  EXPECT_TRUE(same(out, good));
}

TEST(CanFrameCodec, EverySegmentOrderOfAnFdPositionsSample) {
  std::mt19937_64 rng(21);
  const Mode m = kModes[2];
  const GloveSample s = random_sample(rng, m.kind, 0, 100);
  const auto frames = encode(s, true);
  std::vector<std::size_t> order(frames.size());
  std::iota(order.begin(), order.end(), 0);
  std::uint32_t seq = 200;
  do {
    CanSampleDecoder d(kBase, 0, true);
    GloveSample out;
    std::size_t complete = 0;
    for (const std::size_t k : order)
      if (d.feed(frames[k], out) == CanFeedResult::kComplete) ++complete;
    const bool in_order = std::is_sorted(order.begin(), order.end());
    EXPECT_EQ(complete, in_order ? 1u : 0u);
    if (in_order) {
      EXPECT_TRUE(same(out, s));
    } else {
      EXPECT_GE(d.counters().framing_errors, 1u);
    }
    expect_recovers(d, rng, m, seq++);
  } while (std::next_permutation(order.begin(), order.end()));
}

TEST(CanFrameCodec, ShuffledSegmentsNeverDecodeWrongly) {
  std::mt19937_64 rng(22);
  for (const Mode& m : kModes) {
    const GloveSample s = random_sample(rng, m.kind, 0, 7);
    auto frames = encode(s, m.fd);
    for (int trial = 0; trial < 200; ++trial) {
      std::shuffle(frames.begin(), frames.end(), rng);
      CanSampleDecoder d(kBase, 0, m.fd);
      GloveSample out;
      for (const auto& f : frames) {
        if (d.feed(f, out) == CanFeedResult::kComplete) {
          EXPECT_TRUE(same(out, s));
        }
      }
      expect_recovers(d, rng, m, 8);
    }
  }
}

TEST(CanFrameCodec, AMissingSegmentLosesExactlyThatSample) {
  std::mt19937_64 rng(23);
  for (const Mode& m : kModes) {
    for (std::size_t drop = 0; drop < m.segments; ++drop) {
      CanSampleDecoder d(kBase, 0, m.fd);
      const GloveSample lost = random_sample(rng, m.kind, 0, 1);
      const auto frames = encode(lost, m.fd);
      GloveSample out;
      for (std::size_t k = 0; k < frames.size(); ++k) {
        if (k != drop) {
          EXPECT_NE(d.feed(frames[k], out), CanFeedResult::kComplete);
        }
      }
      expect_recovers(d, rng, m, 2);
      EXPECT_EQ(d.counters().framing_errors, 1u) << "drop " << drop;  // one per broken sample
      EXPECT_EQ(d.counters().messages, 1u);
    }
  }
}

TEST(CanFrameCodec, DuplicatedSegmentsAreDroppedAndTheSampleDecodes) {
  std::mt19937_64 rng(24);
  for (const Mode& m : kModes) {
    for (std::size_t dup = 0; dup < m.segments; ++dup) {
      CanSampleDecoder d(kBase, 0, m.fd);
      const GloveSample s = random_sample(rng, m.kind, 0, 1);
      const auto frames = encode(s, m.fd);
      GloveSample out;
      std::size_t complete = 0;
      for (std::size_t k = 0; k < frames.size(); ++k) {
        if (d.feed(frames[k], out) == CanFeedResult::kComplete) ++complete;
        if (k == dup) {
          EXPECT_EQ(d.feed(frames[k], out), CanFeedResult::kDuplicate);
        }
      }
      EXPECT_EQ(complete, 1u);
      EXPECT_TRUE(same(out, s));
      EXPECT_EQ(d.counters().duplicates, 1u);
      EXPECT_EQ(d.counters().framing_errors, 0u);
    }
  }
}

TEST(CanFrameCodec, EverySingleBitFlipIsCaughtOrHarmless) {
  std::mt19937_64 rng(25);
  for (const Mode& m : kModes) {
    const GloveSample s = random_sample(rng, m.kind, 0, 0);
    const auto frames = encode(s, m.fd);
    std::uint64_t caught = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      for (std::size_t byte = 0; byte < frames[k].len; ++byte) {
        for (int bit = 0; bit < 8; ++bit) {
          auto bad = frames;
          bad[k].data[byte] ^= static_cast<std::uint8_t>(1u << bit);
          CanSampleDecoder d(kBase, 0, m.fd);
          GloveSample out;
          bool complete = false;
          for (const auto& f : bad) complete |= d.feed(f, out) == CanFeedResult::kComplete;
          if (complete) {
            EXPECT_TRUE(same(out, s)) << "frame " << k << " byte " << byte << " bit " << bit;  // FD padding only
          } else {
            ++caught;
          }
          expect_recovers(d, rng, m, 1);
        }
      }
    }
    EXPECT_GT(caught, 0u);
  }
}

TEST(CanFrameCodec, CountsSequenceGapsAndRejectsNonFiniteValues) {
  std::mt19937_64 rng(26);
  CanSampleDecoder d(kBase, 0, true);
  GloveSample out;
  for (const std::uint32_t seq : {5u, 6u, 9u, 10u}) {
    CanFeedResult r = CanFeedResult::kPending;
    for (const auto& f : encode(random_sample(rng, SampleKind::kAngles, 0, seq), true)) r = d.feed(f, out);
    EXPECT_EQ(r, CanFeedResult::kComplete);
  }
  EXPECT_EQ(d.counters().sequence_gaps, 2u);
  GloveSample nan = random_sample(rng, SampleKind::kAngles, 0, 11);
  nan.angles[2][1] = std::numeric_limits<float>::quiet_NaN();
  CanFeedResult r = CanFeedResult::kPending;
  for (const auto& f : encode(nan, true)) r = d.feed(f, out);
  EXPECT_EQ(r, CanFeedResult::kFramingError);
  EXPECT_EQ(d.counters().messages, 4u);
}

TEST(CanFrameCodec, EncoderRefusesWhatItCannotEncode) {
  std::mt19937_64 rng(27);
  GloveSample s = random_sample(rng, SampleKind::kPositions, 0, 0);
  std::array<CanFrame, 34> short_span;
  EXPECT_EQ(encode_sample(s, kBase, false, short_span), 0u);
  std::array<CanFrame, kCanMaxSampleFrames> frames;
  s.hand = 2;
  EXPECT_EQ(encode_sample(s, kBase, false, frames), 0u);
  s.hand = 0;
  EXPECT_EQ(encode_sample(s, kCanMaxExtendedId - 0x10, false, frames), 0u);
  s.kind = static_cast<SampleKind>(0);
  EXPECT_EQ(encode_sample(s, kBase, false, frames), 0u);
  // Extended ids work like standard ones.
  s = random_sample(rng, SampleKind::kAngles, 1, 3);
  const std::uint32_t base = 0x18FF0000;
  const std::size_t n = encode_sample(s, base, true, frames);
  CanSampleDecoder d(base, 1, true);
  GloveSample out;
  for (std::size_t k = 0; k < n; ++k) d.feed(frames[k], out);
  EXPECT_TRUE(same(out, s));
}

TEST(CanFrameCodec, ClassicAndFdFramesDoNotMix) {
  std::mt19937_64 rng(28);
  const GloveSample s = random_sample(rng, SampleKind::kAngles, 0, 0);
  CanSampleDecoder classic(kBase, 0, false);
  GloveSample out;
  for (const auto& f : encode(s, true)) EXPECT_EQ(classic.feed(f, out), CanFeedResult::kFramingError);
}

TEST(CanFrameCodec, SeededFuzzNeverCrashesOrDeliversGarbage) {
  std::mt19937_64 rng(29);
  for (const bool fd : {false, true}) {
    CanSampleDecoder d(kBase, 0, fd);
    CanHapticDecoder h(kBase, 0, fd);
    std::vector<GloveSample> sent;
    std::vector<CanFrame> pool;
    std::uint64_t delivered = 0;
    for (int round = 0; round < 3000; ++round) {
      const auto kind = (rng() & 1) ? SampleKind::kPositions : SampleKind::kAngles;
      sent.push_back(random_sample(rng, kind, 0, static_cast<std::uint32_t>(round)));
      auto frames = encode(sent.back(), fd);
      for (auto& f : frames) {
        const auto action = rng() % 128;                                           // about 5 % of frames are damaged
        if (action == 0) continue;                                                 // lost
        if (action == 1) f.data[rng() % 64] ^= static_cast<std::uint8_t>(rng());   // corrupted
        if (action == 2) f.len = static_cast<std::uint8_t>(rng() % 70);            // bad length
        if (action == 3) f.id = kBase + static_cast<std::uint32_t>(rng() % 0x90);  // wrong id
        if (action == 4) {                                                         // pure noise
          f.id = kBase + static_cast<std::uint32_t>(rng() % 0x90);
          f.len = static_cast<std::uint8_t>(rng() % 65);
          for (auto& b : f.data) b = static_cast<std::uint8_t>(rng());
        }
        if (action == 5 && !pool.empty()) f = pool[rng() % pool.size()];  // stale replay
        pool.push_back(f);
        if (pool.size() > 64) pool.erase(pool.begin());
        GloveSample out;
        if (d.feed(f, out) == CanFeedResult::kComplete) {
          ++delivered;
          // Whatever was delivered is exactly one of the samples sent.
          const bool known = std::any_of(sent.begin(), sent.end(), [&](const GloveSample& g) { return same(g, out); });
          EXPECT_TRUE(known) << "round " << round;
        }
        HapticCommand c;
        h.feed(f, c);
      }
    }
    const CanDecoderCounters& c = d.counters();
    EXPECT_EQ(c.messages, delivered);
    EXPECT_GT(delivered, 100u);
    EXPECT_GT(c.framing_errors, 0u);
    EXPECT_GT(c.crc_errors, 0u);
  }
}

}  // namespace
}  // namespace sculpt::hal
