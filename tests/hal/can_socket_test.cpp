// The SocketCAN source and sink on a real socket. Needs a kernel with AF_CAN and a virtual
// CAN interface (ip link add dev vcan0 type vcan && ip link set up vcan0); skips, saying
// which is missing, otherwise. start()'s error messages are checked everywhere.

#include <gtest/gtest.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

#include "sculpt/hal/can_frame_codec.hpp"
#include "can_glove_source.hpp"
#include "can_haptic_sink.hpp"
#include "support/eventually.hpp"

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

// What constructing `Backend` from `config` throws as std::invalid_argument; empty if nothing.
template <typename Backend>
std::string rejection(const CanConfig& config) {
  try {
    Backend backend(config);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CanSocket, RejectsBadConfigAtConstructionNamingTheSetting) {
  CanConfig config;
  config.interface = "";
  EXPECT_EQ(rejection<CanGloveSource>(config), "glove.can.interface: empty");
  EXPECT_EQ(rejection<CanHapticSink>(config), "haptic.can.interface: empty");
  config.interface = "a_name_much_too_long_for_linux";
  EXPECT_EQ(rejection<CanGloveSource>(config),
            "glove.can.interface: 'a_name_much_too_long_for_linux' is longer than 15 characters");
  EXPECT_EQ(rejection<CanHapticSink>(config),
            "haptic.can.interface: 'a_name_much_too_long_for_linux' is longer than 15 characters");
  config.interface = "can0";
  // The last base id whose span of ids still fits in 29 bits is taken; one more is refused.
  config.base_id = kCanMaxExtendedId - kCanIdSpan;
  EXPECT_EQ(rejection<CanGloveSource>(config), "");
  EXPECT_EQ(rejection<CanHapticSink>(config), "");
  config.base_id += 1;
  const std::string too_high = ".base_id: " + std::to_string(config.base_id) + " leaves no room for the " +
                               std::to_string(kCanIdSpan) + " ids after it below 0x1FFFFFFF";
  EXPECT_EQ(rejection<CanGloveSource>(config), "glove.can" + too_high);
  EXPECT_EQ(rejection<CanHapticSink>(config), "haptic.can" + too_high);
}

// Appends a netlink attribute to `message`, whose header says how long it is so far.
void add_attribute(nlmsghdr& message, std::size_t capacity, unsigned short type, const void* data, std::size_t size) {
  const std::size_t at = NLMSG_ALIGN(message.nlmsg_len);
  ASSERT_LE(at + RTA_LENGTH(size), capacity);
  auto* attribute = reinterpret_cast<rtattr*>(reinterpret_cast<char*>(&message) + at);
  attribute->rta_type = type;
  attribute->rta_len = static_cast<unsigned short>(RTA_LENGTH(size));
  if (size > 0) std::memcpy(RTA_DATA(attribute), data, size);
  message.nlmsg_len = static_cast<std::uint32_t>(at + RTA_ALIGN(attribute->rta_len));
}

// Creates vcan0 or deletes it, as `ip link add dev vcan0 type vcan` / `ip link del vcan0`
// do (rtnetlink; needs CAP_NET_ADMIN). Returns 0 or the kernel's errno.
int vcan_link(bool add) {
  struct {
    nlmsghdr header;
    ifinfomsg info;
    char attributes[128];
  } request{};
  request.header.nlmsg_len = NLMSG_LENGTH(sizeof request.info);
  request.header.nlmsg_type = add ? RTM_NEWLINK : RTM_DELLINK;
  request.header.nlmsg_flags = NLM_F_REQUEST | NLM_F_ACK | (add ? NLM_F_CREATE | NLM_F_EXCL : 0);
  request.info.ifi_family = AF_UNSPEC;
  add_attribute(request.header, sizeof request, IFLA_IFNAME, kVcan, std::strlen(kVcan) + 1);
  if (add) {
    const std::size_t link_info = NLMSG_ALIGN(request.header.nlmsg_len);
    add_attribute(request.header, sizeof request, IFLA_LINKINFO, nullptr, 0);
    add_attribute(request.header, sizeof request, IFLA_INFO_KIND, "vcan", 4);
    auto* nest = reinterpret_cast<rtattr*>(reinterpret_cast<char*>(&request) + link_info);
    nest->rta_len = static_cast<unsigned short>(request.header.nlmsg_len - link_info);
  }
  const int s = ::socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE);
  if (s < 0) return errno;
  int result = EIO;
  if (::send(s, &request, request.header.nlmsg_len, 0) == static_cast<ssize_t>(request.header.nlmsg_len)) {
    struct {
      nlmsghdr header;
      nlmsgerr error;
    } ack{};
    if (::recv(s, &ack, sizeof ack, 0) >= static_cast<ssize_t>(sizeof ack) && ack.header.nlmsg_type == NLMSG_ERROR)
      result = -ack.error.error;
  }
  ::close(s);
  return result;
}

class CanSocketVcan : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    const std::string why = af_can_missing();
    if (!why.empty()) GTEST_SKIP() << "AF_CAN not available here: " << why;
    if (::if_nametoindex(kVcan) == 0)
      GTEST_SKIP() << "AF_CAN works but there is no " << kVcan
                   << " (ip link add dev vcan0 type vcan && ip link set up vcan0)";
    open_peer();
  }
  // The test's own socket on vcan0, for CAN FD and classic frames.
  void open_peer() {
    if (peer_ >= 0) ::close(peer_);
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
    if (::if_nametoindex(kVcan) == 0 && vcan_link(true) == 0) set_vcan_up(true);  // a test that removed it failed
    if (interface_was_set_down_) set_vcan_up(true);
    if (peer_ >= 0) ::close(peer_);
  }
  CanConfig vcan_config() const {
    CanConfig config;
    config.interface = kVcan;
    config.fd = GetParam();
    return config;
  }
  // An error frame as a CAN controller's driver would report it: CAN_ERR_FLAG plus the class
  // bits in the id, details in the 8 data bytes (linux/can/error.h).
  void write_error_frame(canid_t error_class, std::uint8_t controller_detail = 0) const {
    can_frame raw{};
    raw.can_id = CAN_ERR_FLAG | error_class;
    raw.len = CAN_ERR_DLC;
    raw.data[1] = controller_detail;
    ASSERT_EQ(::write(peer_, &raw, CAN_MTU), static_cast<ssize_t>(CAN_MTU));
  }
  void write_samples(const CanConfig& config, std::uint32_t first_sequence, std::uint32_t count) const {
    GloveSample s;
    s.hand = 0;
    s.kind = SampleKind::kAngles;
    s.angles[0] = {0.5f, 0.25f, 0.125f, 0.0625f};
    std::array<CanFrame, kCanMaxSampleFrames> frames;
    for (std::uint32_t seq = first_sequence; seq < first_sequence + count; ++seq) {
      s.sequence = seq;
      const std::size_t n = encode_sample(s, config.base_id, config.fd, frames);
      for (std::size_t k = 0; k < n; ++k) write_frame(frames[k]);
    }
  }
  // Brings vcan0 down or up as `ip link set` does (needs CAP_NET_ADMIN); false if refused.
  bool set_vcan_up(bool up) {
    ifreq request{};
    std::strncpy(request.ifr_name, kVcan, IFNAMSIZ - 1);
    if (::ioctl(peer_, SIOCGIFFLAGS, &request) != 0) return false;
    if (up)
      request.ifr_flags = static_cast<short>(request.ifr_flags | IFF_UP);
    else
      request.ifr_flags = static_cast<short>(request.ifr_flags & ~IFF_UP);
    if (::ioctl(peer_, SIOCSIFFLAGS, &request) != 0) return false;
    interface_was_set_down_ = !up;
    // The kernel tells every socket bound to the interface it went down with a pending
    // ENETDOWN, which the next write would return: this socket takes it here.
    int pending = 0;
    socklen_t size = sizeof pending;
    ::getsockopt(peer_, SOL_SOCKET, SO_ERROR, &pending, &size);
    return true;
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
  bool interface_was_set_down_ = false;
};

// Polls `done` every 5 ms for up to 5 s.
using test::eventually;

// What a source has handed out, polled for until there are `want` samples.
struct Received {
  std::array<GloveSample, 16> samples;
  std::size_t count = 0;
  bool until(GloveSource& source, std::size_t want) {
    return eventually([&] {
      count += source.poll(std::span(samples).subspan(count));
      return count >= want;
    });
  }
};

// A running source and sink on one configuration, stopped when the test ends.
struct SourceAndSink {
  explicit SourceAndSink(const CanConfig& config) : source(config), sink(config) {
    source.start();
    sink.start();
  }
  ~SourceAndSink() {
    sink.stop();
    source.stop();
  }
  SourceAndSink(const SourceAndSink&) = delete;
  SourceAndSink& operator=(const SourceAndSink&) = delete;
  CanGloveSource source;
  CanHapticSink sink;
  Received got;
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
  while (!complete && read_frame(f)) {
    EXPECT_EQ(f.fd, fd) << "the sink wrote a frame of the other kind";
    complete = decoder.feed(f, out) == CanFeedResult::kComplete;
  }
  ASSERT_TRUE(complete);
  EXPECT_EQ(out.tick, 77u);
  EXPECT_EQ(out.force, c.force);
  // The sink counts the command once its last frame is written: a contact, of hand 0.
  ASSERT_TRUE(eventually([&] { return sink.sent() == 1; }));
  EXPECT_EQ(sink.delivered_in_contact(0), 1u);
  EXPECT_EQ(sink.delivered_in_contact(1), 0u);
  // A rest (no finger in contact) is delivered, not counted as felt.
  c.tick = 78;
  c.active_mask = 0;
  c.force = {};
  ASSERT_TRUE(sink.send(c));
  complete = false;
  while (!complete && read_frame(f)) complete = decoder.feed(f, out) == CanFeedResult::kComplete;
  ASSERT_TRUE(complete);
  EXPECT_EQ(out.tick, 78u);
  EXPECT_EQ(out.active_mask, 0u);
  ASSERT_TRUE(eventually([&] { return sink.sent() == 2; }));
  EXPECT_EQ(sink.delivered_in_contact(0), 1u);
  sink.stop();
}

// vcan has no controller, so it never goes bus-off or recovers by itself; what can be shown is
// the source's side: error frames as a controller's driver sends them (a controller problem, a
// bus-off, the restart after it) are counted by kind and do not disturb the samples around them.
TEST_P(CanSocketVcan, ErrorFramesAreCountedAndSamplesGoOn) {
  const CanConfig config = vcan_config();
  CanGloveSource source(config);
  source.start();
  write_samples(config, 0, 5);
  write_error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_WARNING);
  write_error_frame(CAN_ERR_BUSOFF);
  write_error_frame(CAN_ERR_RESTARTED);
  write_samples(config, 5, 5);
  Received got;
  ASSERT_TRUE(got.until(source, 10)) << got.count << " samples";
  ASSERT_TRUE(eventually([&] { return source.counters().error_frames >= 3; }));
  for (std::size_t i = 0; i < got.count; ++i) EXPECT_EQ(got.samples[i].sequence, i);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 10u);
  EXPECT_EQ(c.error_frames, 3u);
  EXPECT_EQ(c.bus_off, 1u);
  EXPECT_EQ(c.framing_errors + c.crc_errors + c.sequence_gaps, 0u);
  EXPECT_EQ(source.state(), SourceState::kConnected);
  source.stop();
}

// Remote frames and frames for other ids share the bus with the glove and are none of its
// business: not samples, not errors.
TEST_P(CanSocketVcan, RemoteAndForeignFramesAreIgnored) {
  const CanConfig config = vcan_config();
  CanGloveSource source(config);
  source.start();
  can_frame remote{};
  remote.can_id = config.base_id | CAN_RTR_FLAG;
  remote.len = 8;
  ASSERT_EQ(::write(peer_, &remote, CAN_MTU), static_cast<ssize_t>(CAN_MTU));
  CanFrame foreign;
  foreign.id = config.base_id + kCanIdSpan + 1;
  foreign.fd = config.fd;
  foreign.len = 8;
  foreign.data.fill(0xAB);
  write_frame(foreign);
  write_samples(config, 0, 3);
  Received got;
  ASSERT_TRUE(got.until(source, 3));
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 3u);
  EXPECT_EQ(c.error_frames + c.framing_errors + c.crc_errors + c.sequence_gaps, 0u);
  source.stop();
}

// The interface going down (a USB-CAN adapter's link dropping, `ip link set down`) is a
// disconnect; the sink's writes meanwhile are dropped, not blocked; up again, the next frame
// reconnects the source and the sink's commands go out again.
TEST_P(CanSocketVcan, InterfaceDownIsADisconnectAndUpAReconnect) {
  const CanConfig config = vcan_config();
  SourceAndSink io(config);
  write_samples(config, 0, 2);
  ASSERT_TRUE(io.got.until(io.source, 2));
  if (!set_vcan_up(false)) GTEST_SKIP() << "cannot bring " << kVcan << " down here (" << std::strerror(errno) << ")";
  ASSERT_TRUE(eventually([&] { return io.source.state() == SourceState::kDisconnected; }));
  EXPECT_EQ(io.source.counters().disconnects, 1u);
  HapticCommand c;
  c.tick = 1;
  c.active_mask = 0x1;
  c.force[0] = {0.5f, 0.0f, 0.0f};
  ASSERT_TRUE(io.sink.send(c));
  ASSERT_TRUE(eventually([&] { return io.sink.dropped() >= 1; })) << "a write to a down interface was not dropped";
  EXPECT_EQ(io.sink.sent(), 0u);

  ASSERT_TRUE(set_vcan_up(true));
  write_samples(config, 2, 2);
  ASSERT_TRUE(io.got.until(io.source, 4)) << io.got.count << " samples";
  EXPECT_EQ(io.source.state(), SourceState::kConnected);
  EXPECT_EQ(io.source.counters().reconnects, 1u);
  EXPECT_EQ(io.source.counters().samples, 4u);
  c.tick = 2;
  ASSERT_TRUE(io.sink.send(c));
  ASSERT_TRUE(eventually([&] { return io.sink.sent() >= 1; }));
}

// A USB-CAN adapter unplugged and plugged in again takes its interface away and brings a new
// one of the same name: vcan0 deleted and created again. The source disconnects and, once
// the interface is back, reconnects with the next frame; the sink's commands go out again.
TEST_P(CanSocketVcan, InterfaceRemovedAndAddedAgainIsAReconnect) {
  const CanConfig config = vcan_config();
  SourceAndSink io(config);
  write_samples(config, 0, 2);
  ASSERT_TRUE(io.got.until(io.source, 2));
  const int removed = vcan_link(false);
  if (removed == EPERM) GTEST_SKIP() << "cannot remove " << kVcan << " here (" << std::strerror(removed) << ")";
  ASSERT_EQ(removed, 0) << std::strerror(removed);
  ASSERT_TRUE(eventually([&] { return io.source.state() == SourceState::kDisconnected; }));
  ASSERT_EQ(vcan_link(true), 0);
  ASSERT_TRUE(set_vcan_up(true));
  open_peer();
  // The source reopens its socket on its own schedule: send until a sample gets through.
  std::uint32_t sequence = 2;
  ASSERT_TRUE(eventually([&] {
    write_samples(config, sequence++, 1);
    io.got.count += io.source.poll(std::span(io.got.samples).subspan(io.got.count));
    return io.got.count >= 3;
  })) << "no sample after "
      << kVcan << " came back";
  EXPECT_EQ(io.source.state(), SourceState::kConnected);
  EXPECT_EQ(io.source.counters().disconnects, 1u);
  EXPECT_EQ(io.source.counters().reconnects, 1u);
  HapticCommand c;
  c.tick = 3;
  c.active_mask = 0x1;
  const std::uint64_t sent_before = io.sink.sent();
  ASSERT_TRUE(eventually([&] {
    io.sink.send(c);
    return io.sink.sent() > sent_before;
  })) << "the sink sends nothing after "
      << kVcan << " came back";
}

INSTANTIATE_TEST_SUITE_P(ClassicAndFd, CanSocketVcan, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "fd" : "classic"; });

}  // namespace
}  // namespace sculpt::hal
