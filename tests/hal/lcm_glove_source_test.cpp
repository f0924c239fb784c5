// LcmGloveSource on the real LCM code path: memq:// (one shared instance, deterministic) for
// behaviour, and one udpm:// loopback test for the transport a station uses.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "lcm_glove_source.hpp"
#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/hal/tcpq_probe.hpp"
#include "fake_tcpq_server.hpp"
#include "sculpt_lcm/haptic_command_t.hpp"

namespace sculpt::hal {
namespace {

using testing_support::accept_client;
using testing_support::eventually_within_10s;
using testing_support::listen_on;
using testing_support::LoopbackListener;
using testing_support::send_word;
using testing_support::serve_handshake;

GloveSample make_sample(std::uint8_t hand, std::uint32_t sequence) {
  GloveSample s;
  s.hand = hand;
  s.kind = SampleKind::kPositions;
  s.sequence = sequence;
  s.device_time_us = 1000ull * sequence;
  for (std::size_t j = 0; j < kJointPoints; ++j) {
    s.joints[j] = {static_cast<float>(sequence) * 0.001f, static_cast<float>(j), -0.5f};
  }
  return s;
}

std::vector<std::uint8_t> encode_lcm(const GloveSample& s) {
  sculpt_lcm::glove_sample_t m{};
  hal::to_lcm(s, 0, m);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

void publish(lcm::LCM& lcm, const std::string& channel, const std::vector<std::uint8_t>& bytes) {
  ASSERT_EQ(lcm.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())), 0);
}

void publish(lcm::LCM& lcm, const GloveSample& s) { publish(lcm, "SCULPT_GLOVE", encode_lcm(s)); }

/// Waits until the source has dealt with `count` messages (queued, overflowed or refused).
void wait_handled(const LcmGloveSource& source, std::uint64_t count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  auto handled = [&] {
    const SourceCounters c = source.counters();
    return c.samples + c.overflows + c.framing_errors;
  };
  while (handled() < count && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(handled(), count);
}

std::vector<GloveSample> drain(LcmGloveSource& source) {
  std::vector<GloveSample> got;
  std::array<GloveSample, 8> buffer;
  for (std::size_t n; (n = source.poll(buffer)) > 0;)
    got.insert(got.end(), buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n));
  return got;
}

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

TEST(LcmGloveSource, DeliversSamplesInOrderStampedOnReceipt) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LcmGloveSource source(lcm, LcmConfig{}, 64);
  EXPECT_EQ(source.state(), SourceState::kStopped);
  source.start();
  EXPECT_EQ(source.state(), SourceState::kConnected);
  EXPECT_STREQ(source.name(), "lcm");

  const std::int64_t before = monotonic_ns();
  for (std::uint32_t i = 0; i < 20; ++i) publish(lcm, make_sample(static_cast<std::uint8_t>(i % 2), i / 2));
  wait_handled(source, 20);
  const std::int64_t after = monotonic_ns();
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 20u);
  for (std::uint32_t i = 0; i < 20; ++i) {
    const GloveSample want = make_sample(static_cast<std::uint8_t>(i % 2), i / 2);
    EXPECT_EQ(got[i].hand, want.hand);
    EXPECT_EQ(got[i].sequence, want.sequence);
    EXPECT_EQ(got[i].device_time_us, want.device_time_us);
    EXPECT_EQ(got[i].joints, want.joints);
    EXPECT_GE(got[i].receive_time_ns, before);
    EXPECT_LE(got[i].receive_time_ns, after);
    if (i > 0) {
      EXPECT_GE(got[i].receive_time_ns, got[i - 1].receive_time_ns);
    }
  }
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 20u);
  EXPECT_EQ(c.framing_errors, 0u);
  EXPECT_EQ(c.sequence_gaps, 0u);
  EXPECT_EQ(c.overflows, 0u);
  source.stop();
  EXPECT_EQ(source.state(), SourceState::kStopped);
  source.stop();  // idempotent
}

TEST(LcmGloveSource, CorruptMessagesAreFramingErrorsAndTheNextGoodSampleArrives) {
  lcm::LCM lcm("memq://");
  LcmGloveSource source(lcm, LcmConfig{}, 64);
  source.start();

  const auto good = encode_lcm(make_sample(0, 1));
  publish(lcm, "SCULPT_GLOVE", std::vector<std::uint8_t>{0xde, 0xad, 0xbe, 0xef, 0x00, 0x01});  // garbage
  publish(lcm, "SCULPT_GLOVE", std::vector<std::uint8_t>(good.begin(), good.begin() + 100));    // truncated
  auto trailing = good;
  trailing.push_back(0);
  publish(lcm, "SCULPT_GLOVE", trailing);  // a glove_sample_t and then some: not one
  auto flipped = good;
  flipped[3] ^= 0x40;  // inside the type fingerprint
  publish(lcm, "SCULPT_GLOVE", flipped);
  {
    sculpt_lcm::haptic_command_t other{};  // well formed, wrong type
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(other.getEncodedSize()));
    other.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    publish(lcm, "SCULPT_GLOVE", bytes);
  }
  {
    GloveSample bad = make_sample(0, 1);
    bad.joints[6][1] = std::nanf("");  // decodes, but is not a usable sample
    publish(lcm, bad);
    sculpt_lcm::glove_sample_t m{};
    hal::to_lcm(make_sample(0, 1), 0, m);
    m.hand = 3;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    publish(lcm, "SCULPT_GLOVE", bytes);
  }
  publish(lcm, "SCULPT_GLOVE", good);
  wait_handled(source, 8);
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].sequence, 1u);
  EXPECT_EQ(got[0].hand, 0u);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.framing_errors, 7u);
  EXPECT_EQ(c.samples, 1u);
  EXPECT_EQ(source.state(), SourceState::kConnected);
}

TEST(LcmGloveSource, SequenceGapsAreCountedPerHandAndSurviveWrapAround) {
  lcm::LCM lcm("memq://");
  LcmGloveSource source(lcm, LcmConfig{}, 64);
  source.start();
  // Left: 1, 2, 5 (3 and 4 missing). Right: 0xFFFFFFFE, 0xFFFFFFFF, 0, 1 (wraps, no gap),
  // interleaved with the left hand, whose numbers must not be compared with the right's.
  const std::vector<std::pair<std::uint8_t, std::uint32_t>> sent = {
      {0, 1}, {1, 0xFFFF'FFFEu}, {0, 2}, {1, 0xFFFF'FFFFu}, {1, 0}, {0, 5}, {1, 1}};
  for (const auto& [hand, seq] : sent) publish(lcm, make_sample(hand, seq));
  wait_handled(source, sent.size());
  EXPECT_EQ(source.counters().sequence_gaps, 2u);
  // A duplicate or a step back (a device restart) resynchronises without a gap; the next
  // step after it is measured from there.
  publish(lcm, make_sample(0, 5));
  publish(lcm, make_sample(0, 0));
  publish(lcm, make_sample(0, 3));  // 1 and 2 missing
  wait_handled(source, sent.size() + 3);
  EXPECT_EQ(source.counters().sequence_gaps, 4u);
  EXPECT_EQ(drain(source).size(), sent.size() + 3);
}

TEST(LcmGloveSource, FullQueueCountsOverflowsAndKeepsTheOldest) {
  lcm::LCM lcm("memq://");
  LcmGloveSource source(lcm, LcmConfig{}, 4);
  source.start();
  for (std::uint32_t i = 0; i < 7; ++i) publish(lcm, make_sample(1, i));
  wait_handled(source, 7);
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.samples, 4u);
  EXPECT_EQ(c.overflows, 3u);
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got.front().sequence, 0u);
  EXPECT_EQ(got.back().sequence, 3u);
}

TEST(LcmGloveSource, PollFillsAtMostTheSpanItIsGiven) {
  lcm::LCM lcm("memq://");
  LcmGloveSource source(lcm, LcmConfig{}, 16);
  source.start();
  for (std::uint32_t i = 0; i < 5; ++i) publish(lcm, make_sample(0, i));
  wait_handled(source, 5);
  std::array<GloveSample, 3> buffer;
  EXPECT_EQ(source.poll(buffer), 3u);
  EXPECT_EQ(buffer[2].sequence, 2u);
  EXPECT_EQ(source.poll(buffer), 2u);
  EXPECT_EQ(buffer[1].sequence, 4u);
  EXPECT_EQ(source.poll(buffer), 0u);
}

TEST(LcmGloveSource, ListensOnTheConfiguredChannelOnly) {
  lcm::LCM lcm("memq://");
  LcmConfig config;
  config.glove_channel = "STATION_B_GLOVE";
  LcmGloveSource source(lcm, config, 16);
  source.start();
  publish(lcm, make_sample(0, 1));  // default channel: not ours
  publish(lcm, "STATION_B_GLOVE", encode_lcm(make_sample(0, 2)));
  wait_handled(source, 1);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto got = drain(source);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].sequence, 2u);
}

TEST(LcmGloveSource, BadUrlThrowsNamingItAndRestartWorks) {
  LcmConfig config;
  config.url = "nosuchprovider://glove";
  LcmGloveSource bad(config, 8);
  try {
    bad.start();
    FAIL() << "start() should have thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchprovider://glove"), std::string::npos) << e.what();
  }
  EXPECT_EQ(bad.state(), SourceState::kStopped);

  config.url = "memq://";  // owned instance: nothing else can publish on it, but it runs
  LcmGloveSource owned(config, 8);
  owned.start();
  EXPECT_THROW(owned.start(), std::runtime_error);
  owned.stop();
  owned.start();
  EXPECT_EQ(owned.state(), SourceState::kConnected);
  owned.stop();
}

// liblcm 1.3.1's tcpq instance has no socket while its server is unreachable, and handleTimeout
// then hands -1 to FD_SET, which aborts the process: `sculpt run --lcm tcpq://...` with no server
// died with "bit out of range". No server: start() says so. A server that answers and then hangs
// up: the source reports the glove disconnected and keeps running, and stop() returns.
TEST(LcmGloveSource, ATcpqServerMissingOrGoneIsAnErrorNotAnAbort) {
  LcmConfig config;
  {
    LoopbackListener free_port;
    config.url = free_port.url();
  }  // closed: nothing listens there now
  LcmGloveSource unanswered(config, 8);
  try {
    unanswered.start();
    ADD_FAILURE() << "start() should have thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "LCM glove source: no server answered at '" + config.url + "'");
  }
  EXPECT_EQ(unanswered.state(), SourceState::kStopped);

  // The server's side of LCM's tcpq handshake: the client's magic and version in, the server's
  // out (big-endian words), then the client's subscription, then it hangs up.
  LoopbackListener server;
  config.url = server.url();
  std::thread serve([&server] {
    const int client = accept_client(server.fd());
    if (client < 0) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ::close(client);
  });
  LcmGloveSource source(config, 8);
  source.start();
  serve.join();
  server.close();
  eventually_within_10s([&] { return source.counters().disconnects > 0; });
  EXPECT_EQ(source.counters().disconnects, 1u);
  // Still running, through several back-offs, on an instance with no socket.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(source.state(), SourceState::kDisconnected);
  source.stop();
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

// A tcpq server that hangs up and comes back: the source used to stay disconnected until the
// station was restarted (liblcm 1.3.1 reconnects only in its blocking handle()). It now looks
// for the server every second and, once it answers, listens on a new instance: the glove's
// next sample arrives, counted as a reconnect. The server is named by its address, and by a host
// name (looked up once, at start: the looks and the new instance use the address, since a
// lookup could wait as long as the resolver does).
class LcmGloveSourceTcpqHost : public testing::TestWithParam<const char*> {};

TEST_P(LcmGloveSourceTcpqHost, ATcpqServerThatComesBackIsListenedToAgain) {
  LoopbackListener first;
  const std::string by_address = first.url();
  const auto port = static_cast<std::uint16_t>(std::stoi(by_address.substr(by_address.rfind(':') + 1)));
  LcmConfig config;
  config.url = std::string("tcpq://") + GetParam() + ":" + std::to_string(port);
  std::thread hang_up([&first] {
    const int client = accept_client(first.fd());
    if (client >= 0) ::close(client);
  });
  LcmGloveSource source(config, 8);
  source.start();
  hang_up.join();
  first.close();  // gone: the looks are refused
  ASSERT_TRUE(eventually_within_10s([&] { return source.counters().disconnects == 1; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // a look or two finds nothing
  EXPECT_EQ(source.state(), SourceState::kDisconnected);
  EXPECT_EQ(source.counters().reconnects, 0u);

  const int back = listen_on(port);
  ASSERT_GE(back, 0) << "cannot listen on port " << port << " again";
  // Every client is answered, as LCM's own server does: the look (which hangs up after the
  // handshake), the new
  // instance (sent one sample), and the old instance, which liblcm connects once more while
  // destroying it (its destroy unsubscribes, and a tcpq instance without a socket connects to
  // unsubscribe).
  std::thread serve([&] {
    std::vector<int> clients;
    bool sent = false;
    for (int client = ::accept(back, nullptr, nullptr); client >= 0; client = ::accept(back, nullptr, nullptr)) {
      clients.push_back(client);
      if (!serve_handshake(client) || sent) continue;
      const std::vector<std::uint8_t> data = encode_lcm(make_sample(0, 7));
      const std::string channel = config.glove_channel;
      send_word(client, 1);  // a published message: type, channel, payload
      send_word(client, static_cast<std::uint32_t>(channel.size()));
      (void)::send(client, channel.data(), channel.size(), MSG_NOSIGNAL);
      send_word(client, static_cast<std::uint32_t>(data.size()));
      (void)::send(client, data.data(), data.size(), MSG_NOSIGNAL);
      sent = true;
    }
    for (const int client : clients) ::close(client);
  });
  std::array<GloveSample, 4> out{};
  std::size_t received = 0;
  EXPECT_TRUE(eventually_within_10s([&] { return (received += source.poll(out)) > 0; }));
  EXPECT_EQ(received, 1u);
  EXPECT_EQ(out[0].sequence, 7u);
  EXPECT_TRUE(eventually_within_10s([&] { return source.state() == SourceState::kConnected; }));
  EXPECT_EQ(source.counters().reconnects, 1u);
  source.stop();
  ::shutdown(back, SHUT_RDWR);  // wakes the accept
  serve.join();
  ::close(back);
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

INSTANTIATE_TEST_SUITE_P(AddressAndHostName, LcmGloveSourceTcpqHost, testing::Values("127.0.0.1", "localhost"));

// A tcpq server that hung up and then stopped answering (its process stopped or hung, or its
// host gone from the network): the source's instance has no socket, and liblcm's destroy
// connects to the server to unsubscribe and waits for its handshake, without a timeout. stop()
// (the station's end, a scene's restart) waited with it, for ever here. It now returns at once.
// The listener stands for that server: it never accepts, so its kernel queues the connects
// (which then wait for a handshake that never comes) until the queue is full, and drops the
// rest (which wait as for a host that has gone).
TEST(LcmGloveSource, StopReturnsWhileTheTcpqServerDoesNotAnswer) {
  LoopbackListener server;
  LcmConfig config;
  config.url = server.url();
  std::thread hang_up([&server] {
    const int client = accept_client(server.fd());
    if (client >= 0) ::close(client);
  });
  LcmGloveSource source(config, 8);
  source.start();
  hang_up.join();
  eventually_within_10s([&] { return source.counters().disconnects > 0; });
  ASSERT_EQ(source.counters().disconnects, 1u);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // the source's looks get no answer
  EXPECT_FALSE(tcpq_server_answers(config.url, 200));
  EXPECT_EQ(source.counters().reconnects, 0u);

  auto stopping = std::async(std::launch::async, [&source] { source.stop(); });
  const bool returned = stopping.wait_for(std::chrono::seconds(3)) == std::future_status::ready;
  EXPECT_TRUE(returned) << "stop() waited for a server that does not answer";
  server.close();  // refused from here on: a connect or handshake still waiting fails
  stopping.wait();
  EXPECT_EQ(source.state(), SourceState::kStopped);
  // The instance was let go on a thread of its own, which the refusal now ends.
  EXPECT_TRUE(eventually_within_10s([] { return lcm_destroys_in_flight() == 0; }));
}

// start() looks before liblcm connects: a server that queues the connection and never answers
// the handshake held the constructor of liblcm's instance, so start() never returned.
TEST(LcmGloveSource, StartSaysNoServerAnsweredWhenTheServerDoesNotHandshake) {
  LoopbackListener server;  // never accepts
  LcmConfig config;
  config.url = server.url();
  LcmGloveSource source(config, 8);
  EXPECT_EQ(testing_support::start_within_3_s(source, server),
            "LCM glove source: no server answered at '" + config.url + "'");
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

// A tcpq host name with no address is said at start, named as the scene wrote it.
TEST(LcmGloveSource, StartSaysATcpqHostHasNoAddress) {
  LcmConfig config;
  config.url = "tcpq://glove..invalid:7700";  // an empty label: the resolver refuses it at once
  LcmGloveSource source(config, 8);
  try {
    source.start();
    ADD_FAILURE() << "started on a host with no address";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "LCM glove source: no address for the host in '" + config.url + "'");
  }
  EXPECT_EQ(source.state(), SourceState::kStopped);
}

// The station's transport: UDP multicast on loopback (ttl=0). Multicast drops bursts here, so
// a modest number of samples go out with pauses, and the test checks that what arrived is
// exactly what was sent, in order, and that the gaps account for what did not.
TEST(LcmGloveSource, UdpmLoopbackDeliversWhatWasSent) {
  const int port = 17000 + static_cast<int>(getpid() % 5000);  // unique per test run
  LcmConfig config;
  config.url = "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0";
  lcm::LCM sender(config.url);
  if (!sender.good()) GTEST_SKIP() << "cannot open " << config.url << " (no multicast route?)";
  LcmGloveSource source(config, 64);
  try {
    source.start();
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << e.what();
  }
  constexpr std::uint32_t kSent = 30;
  std::vector<GloveSample> got;
  for (std::uint32_t i = 0; i < kSent; ++i) {
    const auto bytes = encode_lcm(make_sample(1, i));
    if (sender.publish("SCULPT_GLOVE", bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
      GTEST_SKIP() << "publish on " << config.url << " failed (no multicast route?)";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
    auto more = drain(source);
    got.insert(got.end(), more.begin(), more.end());
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  while (std::chrono::steady_clock::now() < deadline && (got.empty() || got.back().sequence + 1 < kSent)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    auto more = drain(source);
    got.insert(got.end(), more.begin(), more.end());
  }
  source.stop();
  if (got.empty()) GTEST_SKIP() << "nothing arrived on " << config.url << " (multicast loopback disabled?)";
  for (std::size_t i = 0; i < got.size(); ++i) {
    const GloveSample want = make_sample(1, got[i].sequence);
    EXPECT_EQ(got[i].joints, want.joints);
    EXPECT_EQ(got[i].device_time_us, want.device_time_us);
    if (i > 0) {
      EXPECT_GT(got[i].sequence, got[i - 1].sequence);
    }
  }
  const SourceCounters c = source.counters();
  EXPECT_EQ(c.framing_errors, 0u);
  EXPECT_EQ(c.samples, got.size());
  EXPECT_EQ(c.samples + c.sequence_gaps, got.back().sequence - got.front().sequence + 1);
  // Loopback with pauses loses little; most must arrive.
  EXPECT_GE(got.size(), kSent / 2) << "only " << got.size() << " of " << kSent << " arrived";
}

}  // namespace
}  // namespace sculpt::hal
