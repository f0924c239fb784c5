// The USB source and the USB haptic sink against a real USB device in a booted kernel: the
// FunctionFS glove (tests/guest/ffs_glove.cpp) on dummy_hcd, set up by tests/guest/usb.sh,
// which names the configfs gadget in GLOVE_GADGET and the file where the glove logs the haptic
// frames it decoded in GLOVE_HAPTIC_LOG. Skips, saying so, anywhere else.

#include <gtest/gtest.h>

#include <libusb.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "usb_glove_source.hpp"
#include "usb_haptic_sink.hpp"
#include "support/eventually.hpp"

namespace sculpt::hal {
namespace {

constexpr std::uint16_t kVendor = 0x1209;  // pid.codes' test ids, as usb.sh gives the gadget
constexpr std::uint16_t kProduct = 0x0001;

std::string gadget() {
  const char* g = std::getenv("GLOVE_GADGET");
  return g != nullptr ? g : "";
}

// Binds the gadget to the controller usb.sh named, or unbinds it ("" = unplug).
bool set_udc(const std::string& udc) {
  std::ofstream file(gadget() + "/UDC");
  file << udc << '\n';
  file.close();
  return !file.fail();
}

std::string bound_udc() {
  const char* u = std::getenv("GLOVE_UDC");
  return u != nullptr ? u : "dummy_udc.0";
}

// A guest under software emulation is slow: ten seconds unless told.
bool eventually(const std::function<bool()>& done, std::chrono::seconds timeout = std::chrono::seconds(10)) {
  return test::eventually(done, timeout, std::chrono::milliseconds(10));
}

std::string haptic_log() {
  const char* l = std::getenv("GLOVE_HAPTIC_LOG");
  return l != nullptr ? l : "";
}

// The gadget's endpoints as the host enumerated them (FunctionFS may renumber), and the
// interfaces they are on: samples IN on one, haptic frames OUT on another.
struct Endpoints {
  std::uint8_t in = 0, out = 0;
  int in_interface = -1, out_interface = -1;
};

Endpoints endpoints() {
  Endpoints found;
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) return found;
  libusb_device_handle* h = libusb_open_device_with_vid_pid(ctx, kVendor, kProduct);
  if (h != nullptr) {
    libusb_config_descriptor* config = nullptr;
    if (libusb_get_active_config_descriptor(libusb_get_device(h), &config) == 0) {
      for (int i = 0; i < config->bNumInterfaces; ++i) {
        const libusb_interface_descriptor& alt = config->interface[i].altsetting[0];
        for (int e = 0; e < alt.bNumEndpoints; ++e) {
          const std::uint8_t address = alt.endpoint[e].bEndpointAddress;
          if ((address & LIBUSB_ENDPOINT_IN) != 0) {
            found.in = address;
            found.in_interface = alt.bInterfaceNumber;
          } else {
            found.out = address;
            found.out_interface = alt.bInterfaceNumber;
          }
        }
      }
      libusb_free_config_descriptor(config);
    }
    libusb_close(h);
  }
  libusb_exit(ctx);
  return found;
}

// One haptic frame as the glove decoded it.
struct Received {
  std::uint32_t sequence = 0;
  std::uint64_t device_time_us = 0;
  HapticCommand command;
};

// What the glove logged (ffs_glove.cpp has the format): complete lines only, since the glove
// may be writing the last one.
struct GloveLog {
  std::vector<Received> frames;
  std::uint64_t crc_errors = 0, framing_errors = 0;
  bool malformed = false;
};

GloveLog read_glove_log() {
  GloveLog log;
  std::ifstream file(haptic_log());
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::size_t begin = 0;
  for (std::size_t end; (end = text.find('\n', begin)) != std::string::npos; begin = end + 1) {
    std::istringstream line(text.substr(begin, end - begin));
    std::string kind;
    line >> kind;
    if (kind == "E") {
      line >> log.crc_errors >> log.framing_errors;
    } else if (kind == "F") {
      Received r;
      unsigned hand = 0, mask = 0;
      line >> r.sequence >> r.device_time_us >> hand >> r.command.tick >> mask;
      r.command.hand = static_cast<std::uint8_t>(hand);
      r.command.active_mask = static_cast<std::uint8_t>(mask);
      for (auto& force : r.command.force)
        for (float& component : force) {
          std::string word;
          line >> word;
          component = std::strtof(word.c_str(), nullptr);  // hex floats read back exactly
        }
      if (line.fail()) log.malformed = true;
      log.frames.push_back(r);
    } else {
      log.malformed = true;
    }
  }
  return log;
}

// The frames whose tick is in [first, last], in the order the glove received them.
std::vector<Received> frames_with_ticks(const GloveLog& log, std::uint32_t first, std::uint32_t last) {
  std::vector<Received> out;
  for (const Received& r : log.frames)
    if (r.command.tick >= first && r.command.tick <= last) out.push_back(r);
  return out;
}

bool is_release(const HapticCommand& c) {
  if (c.active_mask != 0) return false;
  for (const Point3f& f : c.force)
    if (f != Point3f{0.0f, 0.0f, 0.0f}) return false;
  return true;
}

double magnitude(const Point3f& v) {
  return std::sqrt(double{v[0]} * v[0] + double{v[1]} * v[1] + double{v[2]} * v[2]);
}

// A command every value of which follows from its number i: hands alternate, forces well
// below the bound.
HapticCommand numbered_command(std::uint32_t tick, std::uint32_t i) {
  HapticCommand c;
  c.hand = static_cast<std::uint8_t>(i % kHands);
  c.tick = tick;
  c.active_mask = static_cast<std::uint8_t>(i % 32);
  for (std::size_t f = 0; f < kFingers; ++f)
    c.force[f] = {0.01f * static_cast<float>(i), -0.1f * static_cast<float>(f), 0.05f * static_cast<float>(f + 1)};
  return c;
}

HapticCommand command_of(std::uint8_t hand, std::uint32_t tick, std::uint8_t active_mask) {
  HapticCommand c;
  c.hand = hand;
  c.tick = tick;
  c.active_mask = active_mask;
  return c;
}

void expect_same(const HapticCommand& got, const HapticCommand& sent) {
  EXPECT_EQ(got.hand, sent.hand) << "tick " << sent.tick;
  EXPECT_EQ(got.tick, sent.tick);
  EXPECT_EQ(got.active_mask, sent.active_mask) << "tick " << sent.tick;
  EXPECT_EQ(got.force, sent.force) << "tick " << sent.tick;  // bit for bit
}

constexpr float kMaxForce = 4.0f;

class UsbGadget : public ::testing::Test {
 protected:
  void SetUp() override {
    if (gadget().empty()) GTEST_SKIP() << "no FunctionFS glove here (GLOVE_GADGET unset; scripts/guest_test.sh usb)";
    ASSERT_FALSE(haptic_log().empty()) << "GLOVE_HAPTIC_LOG unset";
    Endpoints e;
    ASSERT_TRUE(eventually([&] { return (e = endpoints()).in != 0 && e.out != 0; }))
        << "no device " << std::hex << kVendor << ":" << kProduct << " with an IN and an OUT endpoint";
    ASSERT_NE(e.in_interface, e.out_interface) << "the glove's IN and OUT endpoints share an interface";
    config_.vendor_id = kVendor;
    config_.product_id = kProduct;
    config_.transfer = UsbConfig::Transfer::kBulk;
    config_.interface_number = e.in_interface;
    config_.endpoint = e.in;
    haptic_config_ = config_;
    haptic_config_.interface_number = e.out_interface;
    haptic_config_.out_endpoint = e.out;
  }
  void TearDown() override {
    const GloveLog log = read_glove_log();
    EXPECT_FALSE(log.malformed) << haptic_log() << " has a line the test cannot read";
    EXPECT_EQ(log.crc_errors, 0u) << "the glove rejected haptic frames";
    EXPECT_EQ(log.framing_errors, 0u) << "the glove rejected haptic frames";
  }
  // Polls until `want` samples in all have come; false after 10 s.
  bool receive(UsbGloveSource& source, std::size_t want) {
    return eventually([&] {
      received_ += source.poll(std::span(buffer_));
      return received_ >= want;
    });
  }
  UsbConfig config_;
  UsbConfig haptic_config_;
  std::array<GloveSample, 64> buffer_{};
  std::size_t received_ = 0;
};

TEST_F(UsbGadget, SourceReadsTheGlovesFrames) {
  UsbGloveSource source(config_);
  source.start();
  ASSERT_TRUE(receive(source, 50)) << received_ << " samples";
  EXPECT_EQ(source.state(), SourceState::kConnected);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.crc_errors + c.framing_errors, 0u);
  EXPECT_EQ(buffer_[0].kind, SampleKind::kAngles);
  EXPECT_FLOAT_EQ(buffer_[0].angles[1][0], 0.1f);
  source.stop();
}

TEST_F(UsbGadget, UnbindingTheControllerIsAnUnplugAndRebindingAReconnect) {
  UsbGloveSource source(config_);
  source.start();
  ASSERT_TRUE(receive(source, 20));
  ASSERT_TRUE(set_udc("")) << "cannot unbind " << gadget();
  const bool gone = eventually([&] { return source.state() == SourceState::kDisconnected; });
  ASSERT_TRUE(set_udc(bound_udc())) << "cannot bind " << gadget() << " to " << bound_udc();
  ASSERT_TRUE(gone) << "the source did not notice the unplug";
  EXPECT_EQ(source.counters().disconnects, 1u);
  const std::size_t before = received_;
  ASSERT_TRUE(eventually([&] { return source.state() == SourceState::kConnected; })) << "no reconnect";
  ASSERT_TRUE(receive(source, before + 20)) << "no samples after the reconnect";
  EXPECT_EQ(source.counters().reconnects, 1u);
  source.stop();
}

TEST_F(UsbGadget, SinkFramesArriveDecodedWithTheValuesSent) {
  UsbHapticSink sink(haptic_config_, kMaxForce);
  sink.start();
  EXPECT_TRUE(sink.connected());
  constexpr std::uint32_t kFirst = 1000, kCount = 40;
  for (std::uint32_t i = 0; i < kCount; ++i) {
    ASSERT_TRUE(sink.send(numbered_command(kFirst + i, i)));
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
  // Every command is accounted for: written, replaced by a newer one of its hand, or dropped;
  // and the silence after the last one released both hands.
  ASSERT_TRUE(eventually([&] {
    return sink.delivered() + sink.superseded() + sink.dropped() == kCount && sink.releases() >= 2;
  })) << sink.delivered()
      << " delivered, " << sink.superseded() << " superseded, " << sink.dropped() << " dropped, " << sink.releases()
      << " released";
  std::vector<Received> got, releases;
  ASSERT_TRUE(eventually([&] {
    got.clear();
    releases.clear();
    for (const Received& r : frames_with_ticks(read_glove_log(), kFirst, kFirst + kCount - 1))
      (is_release(r.command) ? releases : got).push_back(r);  // a numbered command always has force
    return got.size() + releases.size() >= sink.delivered() + sink.releases();
  })) << got.size()
      << " frames arrived of " << sink.delivered() << " written";
  EXPECT_EQ(got.size(), sink.delivered()) << "a frame arrived twice, or one not written";
  // What each hand felt: the frames that arrived with a finger in contact (i % 32 == 0 rests).
  std::array<std::uint64_t, kHands> in_contact{};
  for (const Received& r : got) in_contact[r.command.hand] += r.command.active_mask != 0;
  for (std::size_t hand = 0; hand < kHands; ++hand) {
    EXPECT_EQ(sink.delivered_in_contact(hand), in_contact[hand]) << "hand " << hand;
    EXPECT_GT(in_contact[hand], 0u) << "hand " << hand;
  }
  EXPECT_EQ(releases.size(), sink.releases());
  EXPECT_GE(sink.delivered(), kCount / 2) << "the sink wrote fewer than half of the commands, given 3 ms apart";
  EXPECT_EQ(sink.dropped(), 0u);
  EXPECT_EQ(sink.clamped(), 0u);
  for (std::size_t k = 0; k < got.size(); ++k) {
    const std::uint32_t i = got[k].command.tick - kFirst;
    expect_same(got[k].command, numbered_command(kFirst + i, i));
    if (k > 0) {
      EXPECT_GT(got[k].sequence, got[k - 1].sequence) << "frames out of order";
      EXPECT_GE(got[k].device_time_us, got[k - 1].device_time_us);
    }
  }
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back().command.tick, kFirst + kCount - 1) << "the newest command never arrived";
  EXPECT_EQ(got.front().sequence, 0u) << "sequence numbers count from 0 at start";
  sink.stop();
}

TEST_F(UsbGadget, SinkBoundsEveryForceItSends) {
  UsbHapticSink sink(haptic_config_, kMaxForce);
  sink.start();
  HapticCommand c = command_of(1, 2000, 0b111);
  c.force[0] = {30.0f, -40.0f, 0.0f};                                  // 50 N: scaled to 4 N
  c.force[1] = {std::numeric_limits<float>::quiet_NaN(), 1.0f, 0.0f};  // zeroed, out of contact
  c.force[2] = {1.0f, 2.0f, 2.0f};                                     // 3 N: as it is
  c.force[3] = {0.0f, 0.0f, -std::numeric_limits<float>::infinity()};  // zeroed
  ASSERT_TRUE(sink.send(c));
  std::vector<Received> got;
  ASSERT_TRUE(eventually([&] { return !(got = frames_with_ticks(read_glove_log(), 2000, 2000)).empty(); }))
      << "the bounded command never arrived (" << sink.dropped() << " dropped)";
  const HapticCommand& h = got.front().command;
  EXPECT_EQ(h.hand, 1);
  EXPECT_EQ(h.active_mask, 0b101);
  EXPECT_LE(magnitude(h.force[0]), kMaxForce * (1 + 1e-6));
  EXPECT_NEAR(magnitude(h.force[0]), kMaxForce, 1e-5);
  EXPECT_NEAR(h.force[0][0], 2.4f, 1e-6);  // the direction kept: 4 N along (0.6, -0.8, 0)
  EXPECT_NEAR(h.force[0][1], -3.2f, 1e-6);
  EXPECT_EQ(h.force[0][2], 0.0f);
  EXPECT_EQ(h.force[1], (Point3f{0.0f, 0.0f, 0.0f}));
  EXPECT_EQ(h.force[2], (Point3f{1.0f, 2.0f, 2.0f}));
  EXPECT_EQ(h.force[3], (Point3f{0.0f, 0.0f, 0.0f}));
  EXPECT_EQ(sink.clamped(), 1u);
  sink.stop();
}

TEST_F(UsbGadget, SinkReleasesAHandOnSilenceAndAtStop) {
  UsbHapticSink sink(haptic_config_, kMaxForce);
  sink.start();
  HapticCommand press = command_of(1, 3000, 0b10);
  press.force[1] = {0.0f, 0.0f, -1.5f};
  ASSERT_TRUE(sink.send(press));  // and then nothing: the loop went silent
  std::vector<Received> got;
  ASSERT_TRUE(eventually([&] { return (got = frames_with_ticks(read_glove_log(), 3000, 3000)).size() >= 2; }))
      << got.size() << " frames with tick 3000; no release followed the press";
  expect_same(got[0].command, press);
  EXPECT_TRUE(is_release(got[1].command)) << "the second frame is not a release";
  EXPECT_EQ(got[1].command.hand, 1);
  // The sink's own clock in the frames: the release waited for the silence, and no longer.
  const std::uint64_t waited_us = got[1].device_time_us - got[0].device_time_us;
  EXPECT_GE(waited_us, static_cast<std::uint64_t>(UsbHapticSink::kReleaseAfterNs / 1000));
  EXPECT_LT(waited_us, 1'000'000u) << "released " << waited_us << " us after the press";
  EXPECT_EQ(sink.releases(), 1u);
  // Released, the hand owes nothing more: no second release however long the silence.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(frames_with_ticks(read_glove_log(), 3000, 3000).size(), 2u);
  EXPECT_EQ(sink.releases(), 1u);
  // A hand left pressing when the sink stops is released by stop().
  press.tick = 3001;
  ASSERT_TRUE(sink.send(press));
  sink.stop();
  got = frames_with_ticks(read_glove_log(), 3001, 3001);
  ASSERT_EQ(got.size(), 2u) << "stop() did not write the press and then its release";
  expect_same(got[0].command, press);
  EXPECT_TRUE(is_release(got[1].command));
  EXPECT_EQ(sink.releases(), 2u);
}

// The source and the sink together, each on its own interface, through one unplug: both
// notice it, both come back, and samples and frames flow again.
TEST_F(UsbGadget, SinkAndSourceReconnectAfterTheControllerIsUnboundAndBound) {
  UsbGloveSource source(config_);
  UsbHapticSink sink(haptic_config_, kMaxForce);
  source.start();
  sink.start();
  std::uint32_t tick = 4000;
  const auto command = [](std::uint32_t t) { return numbered_command(t, t % 100); };
  // One command every 2 ms, as a loop would send them, until `done` or 10 s.
  const auto pump = [&](const std::function<bool()>& done) {
    return eventually([&] {
      sink.send(command(tick));
      ++tick;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      return done();
    });
  };
  ASSERT_TRUE(pump([&] { return frames_with_ticks(read_glove_log(), 4000, tick).size() >= 10; }));
  ASSERT_TRUE(receive(source, 20));
  ASSERT_TRUE(set_udc("")) << "cannot unbind " << gadget();
  const bool gone = pump([&] { return sink.disconnects() == 1 && source.state() == SourceState::kDisconnected; });
  const std::uint32_t unplugged_at = tick;
  ASSERT_TRUE(set_udc(bound_udc())) << "cannot bind " << gadget() << " to " << bound_udc();
  ASSERT_TRUE(gone) << "unplug not noticed: sink disconnects " << sink.disconnects() << ", source state "
                    << static_cast<int>(source.state());
  EXPECT_FALSE(sink.connected());
  ASSERT_TRUE(pump([&] { return sink.connected(); })) << "the sink did not reconnect";
  const std::uint32_t reconnected_at = tick;
  ASSERT_TRUE(pump([&] { return frames_with_ticks(read_glove_log(), reconnected_at, tick).size() >= 10; }))
      << "no frames after the reconnect";
  EXPECT_EQ(sink.disconnects(), 1u);
  EXPECT_EQ(sink.reconnects(), 1u);
  EXPECT_GT(sink.dropped(), 0u) << "commands sent while unplugged cannot have been written";
  // What arrived after the reconnect is what was sent, value for value (a release, should the
  // emulated machine have paused the pump for 50 ms, is the sink's own).
  for (const Received& r : frames_with_ticks(read_glove_log(), unplugged_at, tick))
    if (!is_release(r.command)) {
      expect_same(r.command, command(r.command.tick));
    }
  const std::size_t before = received_;
  ASSERT_TRUE(eventually([&] { return source.state() == SourceState::kConnected; })) << "the source did not reconnect";
  ASSERT_TRUE(receive(source, before + 20)) << "no samples after the reconnect";
  EXPECT_EQ(source.counters().reconnects, 1u);
  sink.stop();
  source.stop();
}

}  // namespace
}  // namespace sculpt::hal
