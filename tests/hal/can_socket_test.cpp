// The SocketCAN source and sink on a real socket. Needs a kernel with AF_CAN and a virtual
// CAN interface (ip link add dev vcan0 type vcan && ip link set up vcan0); skips, saying
// which is missing, otherwise. start()'s error messages are checked everywhere.

#include <gtest/gtest.h>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>

#include "sculpt/hal/can_frame_codec.hpp"
#include "can_glove_source.hpp"
#include "can_haptic_sink.hpp"

namespace sculpt::hal {
namespace {

constexpr const char* kVcan = "vcan0";

// Empty when AF_CAN works here, else why not.
std::string af_can_missing() {
  const int s = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (s < 0) return std::strerror(errno);
  ::close(s);
  return {};
}

std::string start_error(CanGloveSource& source) {
  try {
    source.start();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CanSocket, StartExplainsWhatIsMissing) {
  CanConfig config;
  config.interface = "nosuchcan9";
  CanGloveSource source(config);
  const std::string error = start_error(source);
  if (!af_can_missing().empty())
    EXPECT_EQ(error.rfind("socketcan: AF_CAN is not available on this kernel (", 0), 0u) << error;
  else
    EXPECT_EQ(error, "socketcan: no interface 'nosuchcan9'");
  EXPECT_EQ(source.state(), SourceState::kStopped);
  CanHapticSink sink(config);
  EXPECT_THROW(sink.start(), std::runtime_error);
}

TEST(CanSocket, RejectsBadConfigAtConstruction) {
  CanConfig config;
  config.interface = "";
  EXPECT_THROW(CanGloveSource{config}, std::invalid_argument);
  config.interface = "a_name_much_too_long_for_linux";
  EXPECT_THROW(CanGloveSource{config}, std::invalid_argument);
  config.interface = "can0";
  config.base_id = kCanMaxExtendedId;
  EXPECT_THROW(CanGloveSource{config}, std::invalid_argument);
}

class CanSocketVcan : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    const std::string why = af_can_missing();
    if (!why.empty()) GTEST_SKIP() << "AF_CAN not available here: " << why;
    if (::if_nametoindex(kVcan) == 0)
      GTEST_SKIP() << "AF_CAN works but there is no " << kVcan
                   << " (ip link add dev vcan0 type vcan && ip link set up vcan0)";
    peer_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    ASSERT_GE(peer_, 0);
    const int on = 1;
    ASSERT_EQ(::setsockopt(peer_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on), 0);
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(::if_nametoindex(kVcan));
    ASSERT_EQ(::bind(peer_, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  }
  void TearDown() override {
    if (peer_ >= 0) ::close(peer_);
  }
  void write_frame(const CanFrame& f) const {
    canfd_frame raw{};
    raw.can_id = f.id > kCanMaxStandardId ? (f.id | CAN_EFF_FLAG) : f.id;
    raw.len = f.len;
    std::memcpy(raw.data, f.data.data(), f.len);
    const std::size_t mtu = f.fd ? CANFD_MTU : CAN_MTU;
    ASSERT_EQ(::write(peer_, &raw, mtu), static_cast<ssize_t>(mtu));
  }
  bool read_frame(CanFrame& f) const {
    pollfd p{peer_, POLLIN, 0};
    if (::poll(&p, 1, 2000) != 1) return false;
    canfd_frame raw{};
    const ssize_t n = ::read(peer_, &raw, sizeof raw);
    if (n != static_cast<ssize_t>(CAN_MTU) && n != static_cast<ssize_t>(CANFD_MTU)) return false;
    f.id = raw.can_id & CAN_EFF_MASK;
    f.fd = n == static_cast<ssize_t>(CANFD_MTU);
    f.len = raw.len;
    std::memcpy(f.data.data(), raw.data, raw.len);
    return true;
  }
  int peer_ = -1;
};

TEST_P(CanSocketVcan, SourceDecodesSamplesSentByAnotherSocket) {
  const bool fd = GetParam();
  CanConfig config;
  config.interface = kVcan;
  config.fd = fd;
  CanGloveSource source(config);
  source.start();
  GloveSample s;
  s.hand = 1;
  s.kind = SampleKind::kAngles;
  s.angles[1] = {0.1f, 0.2f, 0.3f, 0.4f};
  std::array<CanFrame, kCanMaxSampleFrames> frames;
  for (std::uint32_t seq = 0; seq < 10; ++seq) {
    s.sequence = seq;
    const std::size_t n = encode_sample(s, config.base_id, fd, frames);
    for (std::size_t k = 0; k < n; ++k) write_frame(frames[k]);
  }
  std::array<GloveSample, 16> out;
  std::size_t got = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (got < 10 && std::chrono::steady_clock::now() < give_up) {
    got += source.poll(std::span(out).subspan(got));
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(got, 10u);
  for (std::size_t i = 0; i < got; ++i) {
    EXPECT_EQ(out[i].sequence, i);
    EXPECT_EQ(out[i].hand, 1);
    EXPECT_EQ(out[i].angles[1], s.angles[1]);
    EXPECT_GT(out[i].receive_time_ns, 0);
  }
  EXPECT_EQ(source.counters().samples, 10u);
  source.stop();
}

TEST_P(CanSocketVcan, SinkSendsCommandsAnotherSocketDecodes) {
  const bool fd = GetParam();
  CanConfig config;
  config.interface = kVcan;
  config.fd = fd;
  CanHapticSink sink(config);
  sink.start();
  HapticCommand c;
  c.hand = 0;
  c.tick = 77;
  c.active_mask = 0x3;
  c.force[1] = {1.0f, -2.0f, 0.5f};
  ASSERT_TRUE(sink.send(c));
  CanHapticDecoder decoder(config.base_id, 0, fd);
  HapticCommand out;
  CanFrame f;
  bool complete = false;
  while (!complete && read_frame(f)) complete = decoder.feed(f, out) == CanFeedResult::kComplete;
  ASSERT_TRUE(complete);
  EXPECT_EQ(out.tick, 77u);
  EXPECT_EQ(out.force, c.force);
  sink.stop();
}

INSTANTIATE_TEST_SUITE_P(ClassicAndFd, CanSocketVcan, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "fd" : "classic"; });

}  // namespace
}  // namespace sculpt::hal
