// LcmHapticSink over memq://: what the loop send()s comes out on the haptic channel as
// decodable haptic_command_t, captured by a raw subscriber on the same instance. Over tcpq, to a
// server played by the test: one that stops answering, and one that comes back.

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "fake_tcpq_server.hpp"
#include "lcm_haptic_sink.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/base/clock.hpp"

namespace sculpt::hal {
namespace {

struct Capture {
  std::vector<std::vector<std::uint8_t>> messages;
  std::vector<std::string> channels;
  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Capture* self) {
    const auto* bytes = static_cast<const std::uint8_t*>(rbuf->data);
    self->messages.emplace_back(bytes, bytes + rbuf->data_size);
    self->channels.push_back(channel);
  }
  void wait_for(lcm::LCM& lcm, std::size_t count) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (messages.size() < count && std::chrono::steady_clock::now() < deadline) lcm.handleTimeout(20);
  }
};

HapticCommand make_command(std::uint32_t tick) {
  HapticCommand c;
  c.hand = static_cast<std::uint8_t>(tick % 2);
  c.tick = tick;
  c.active_mask = static_cast<std::uint8_t>(tick & 0x1F);
  for (std::size_t f = 0; f < kFingers; ++f) {
    c.force[f] = {0.1f * static_cast<float>(f), -0.01f * static_cast<float>(tick), 2.0f};
  }
  return c;
}

TEST(LcmHapticSink, PublishesDecodableCommandsOnTheHapticChannel) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  Capture capture;
  lcm.subscribeFunction(".*", &Capture::on_message, &capture);
  LcmConfig config;
  config.haptic_channel = "TEST_HAPTIC";
  LcmHapticSink sink(lcm, config, 16);
  EXPECT_STREQ(sink.name(), "lcm");
  sink.start();
  const std::int64_t before = base::wall_time_us();
  for (std::uint32_t t = 10; t < 13; ++t) EXPECT_TRUE(sink.send(make_command(t)));
  capture.wait_for(lcm, 3);
  sink.stop();
  ASSERT_EQ(capture.messages.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(capture.channels[i], "TEST_HAPTIC");
    sculpt_lcm::haptic_command_t m{};
    const auto& bytes = capture.messages[i];
    ASSERT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    EXPECT_GE(m.utime, before);
    HapticCommand got;
    ASSERT_TRUE(hal::from_lcm(m, got));
    const HapticCommand want = make_command(static_cast<std::uint32_t>(10 + i));
    EXPECT_EQ(got.hand, want.hand);
    EXPECT_EQ(got.tick, want.tick);
    EXPECT_EQ(got.active_mask, want.active_mask);
    EXPECT_EQ(got.force, want.force);
  }
  EXPECT_EQ(sink.published(), 3u);
  EXPECT_EQ(sink.dropped(), 0u);
  EXPECT_EQ(sink.publish_errors(), 0u);
}

// What a hand felt: of the commands published, those of each hand with a finger in contact, as
// the receiver decodes them (rest commands, mask 0, are published but carry no contact).
TEST(LcmHapticSink, CountsEachHandsCommandsInContactAsTheReceiverDecodesThem) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  Capture capture;
  lcm.subscribeFunction("SCULPT_HAPTIC", &Capture::on_message, &capture);
  LcmHapticSink sink(lcm, LcmConfig{}, 64);
  sink.start();
  constexpr std::uint32_t kCommands = 40;  // ticks 0 and 32 (hand 0) rest: mask tick & 0x1F
  for (std::uint32_t t = 0; t < kCommands; ++t) ASSERT_TRUE(sink.send(make_command(t)));
  capture.wait_for(lcm, kCommands);
  sink.stop();
  ASSERT_EQ(capture.messages.size(), kCommands);
  std::array<std::uint64_t, kHands> in_contact{};
  for (const auto& bytes : capture.messages) {
    sculpt_lcm::haptic_command_t m{};
    ASSERT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    HapticCommand got;
    ASSERT_TRUE(hal::from_lcm(m, got));
    if (got.active_mask != 0) ++in_contact[got.hand];
  }
  EXPECT_EQ(in_contact[0], 18u);
  EXPECT_EQ(in_contact[1], 20u);
  for (std::size_t hand = 0; hand < kHands; ++hand)
    EXPECT_EQ(sink.delivered_in_contact(hand), in_contact[hand]) << hand;
  EXPECT_EQ(sink.delivered_in_contact(kHands), 0u);
  EXPECT_EQ(sink.delivered(), kCommands);
}

TEST(LcmHapticSink, FullQueueDropsAreCountedAndStopFlushesTheRest) {
  lcm::LCM lcm("memq://");
  Capture capture;
  lcm.subscribeFunction("SCULPT_HAPTIC", &Capture::on_message, &capture);
  LcmHapticSink sink(lcm, LcmConfig{}, 2);
  // Not started yet: nothing drains the queue.
  EXPECT_TRUE(sink.send(make_command(1)));
  EXPECT_TRUE(sink.send(make_command(2)));
  EXPECT_FALSE(sink.send(make_command(3)));
  EXPECT_EQ(sink.dropped(), 1u);
  sink.start();
  sink.stop();  // publishes what was queued before returning
  EXPECT_EQ(sink.published(), 2u);
  capture.wait_for(lcm, 2);
  ASSERT_EQ(capture.messages.size(), 2u);
  sculpt_lcm::haptic_command_t m{};
  m.decode(capture.messages[1].data(), 0, static_cast<int>(capture.messages[1].size()));
  EXPECT_EQ(m.tick, 2);
  sink.stop();  // idempotent
}

TEST(LcmHapticSink, BadUrlThrowsNamingIt) {
  LcmConfig config;
  config.url = "nosuchprovider://haptic";
  LcmHapticSink sink(config, 4);
  try {
    sink.start();
    FAIL() << "start() should have thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://haptic"), std::string::npos) << e.what();
  }
}

// start() looks before liblcm connects: a server that queues the connection and never answers
// the handshake held the constructor of liblcm's instance, so start() never returned.
TEST(LcmHapticSink, StartSaysNoServerAnsweredWhenTheServerDoesNotHandshake) {
  testing_support::LoopbackListener server;  // never accepts
  LcmConfig config;
  config.url = server.url();
  LcmHapticSink sink(config, 4);
  EXPECT_EQ(testing_support::start_within_3_s(sink, server),
            "LCM haptic sink: no server answered at '" + config.url + "'");
}

// Sends `count` commands `gap` apart.
void send_spaced(LcmHapticSink& sink, std::uint32_t first, std::uint32_t count, std::chrono::milliseconds gap) {
  for (std::uint32_t t = first; t < first + count; ++t) {
    EXPECT_TRUE(sink.send(make_command(t)));
    std::this_thread::sleep_for(gap);
  }
}

// A tcpq server that takes the sink's first command, hangs up, and then answers nothing (its
// process stopped: the kernel still queues connects). liblcm's tcpq instance reconnects inside
// publish(), and its connect and handshake have no timeout: the sink's thread waited there for
// ever, and stop() with it (the station's end). Now the commands meanwhile are counted as not
// published, and stop() returns.
TEST(LcmHapticSink, ATcpqServerThatStopsAnsweringCostsItsCommandsNotTheSinksStop) {
  testing_support::LoopbackListener server;
  LcmConfig config;
  config.url = server.url();
  std::thread take_one([&server] {
    const int client = testing_support::accept_client(server.fd());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the command's last bytes
    if (client >= 0) ::close(client);
  });
  LcmHapticSink sink(config, 64);
  sink.start();
  EXPECT_TRUE(sink.send(make_command(1)));
  take_one.join();
  send_spaced(sink, 2, 30, std::chrono::milliseconds(50));  // 1.5 s: a look or two, unanswered

  auto stopping = std::async(std::launch::async, [&sink] { sink.stop(); });
  const bool returned = stopping.wait_for(std::chrono::seconds(3)) == std::future_status::ready;
  EXPECT_TRUE(returned) << "the sink waited for a server that does not answer";
  server.close();  // refused from here on: a connect or handshake still waiting fails
  stopping.wait();
  EXPECT_EQ(sink.published() + sink.publish_errors(), 31u) << "each command published or counted";
  EXPECT_GE(sink.published(), 1u);
  EXPECT_GE(sink.publish_errors(), 29u);
  EXPECT_EQ(sink.dropped(), 0u);
}

// A tcpq server that hangs up and comes back: once it answers a look, the sink publishes to it
// again (liblcm reconnects inside the next publish). Named by its address, and by a host name
// (looked up once, at start: the looks use the address).
class LcmHapticSinkTcpqHost : public testing::TestWithParam<const char*> {};

TEST_P(LcmHapticSinkTcpqHost, ATcpqServerThatComesBackIsPublishedToAgain) {
  testing_support::LoopbackListener server;
  const std::string by_address = server.url();
  LcmConfig config;
  config.url = std::string("tcpq://") + GetParam() + by_address.substr(by_address.rfind(':'));
  std::atomic<int> clients_heard{0};
  std::thread serve([&server, &clients_heard] {
    for (;;) {  // every client that sends after its handshake is heard, then hung up on
      const int client = testing_support::accept_client(server.fd());
      if (client < 0) return;
      clients_heard.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the command's last bytes
      ::close(client);
    }
  });
  LcmHapticSink sink(config, 64);
  sink.start();
  std::uint32_t tick = 1;
  testing_support::eventually_within_10s([&] {
    send_spaced(sink, tick++, 1, std::chrono::milliseconds(50));
    return clients_heard.load() >= 2;
  });
  EXPECT_GE(clients_heard.load(), 2) << "the sink did not publish after its server came back";
  sink.stop();
  ::shutdown(server.fd(), SHUT_RDWR);  // wakes the accept
  serve.join();
  EXPECT_GE(sink.published(), 2u);
}

INSTANTIATE_TEST_SUITE_P(AddressAndHostName, LcmHapticSinkTcpqHost, testing::Values("127.0.0.1", "localhost"));

}  // namespace
}  // namespace sculpt::hal
