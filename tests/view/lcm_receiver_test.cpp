// The viewer's live receiver over tcpq, to a server played by the test: it hears what the server
// forwards, and when the server hangs up and comes back it listens again (it used to stop
// receiving for good: the window then showed a station that had gone still).

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "hal/fake_tcpq_server.hpp"
#include "lcm_receiver.hpp"
#include "sculpt/hal/lcm_handle.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"

namespace sculpt::view {
namespace {

namespace support = hal::testing_support;

// Forwards a tick_stats_t for `tick` on the tick channel to a client, as LCM's server does.
void forward_tick(int client, std::int64_t tick) {
  sculpt_lcm::tick_stats_t m{};
  m.tick = tick;
  m.budget_us = 1000.0;
  std::vector<std::uint8_t> data(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(data.data(), 0, static_cast<int>(data.size()));
  const std::string channel = logging::kTickChannel;
  support::send_word(client, 1);  // a published message: type, channel, payload
  support::send_word(client, static_cast<std::uint32_t>(channel.size()));
  (void)::send(client, channel.data(), channel.size(), MSG_NOSIGNAL);
  support::send_word(client, static_cast<std::uint32_t>(data.size()));
  (void)::send(client, data.data(), data.size(), MSG_NOSIGNAL);
}

// Waits up to 10 s for a TickSeen from `receiver`; -1 when none came.
std::int64_t next_tick(LcmReceiver& receiver) {
  std::int64_t seen = -1;
  support::eventually_within_10s([&] {
    for (const LiveMessage& m : receiver.take()) {
      if (const auto* tick = std::get_if<TickSeen>(&m)) {
        seen = tick->tick;
        return true;
      }
    }
    return false;
  });
  return seen;
}

TEST(LcmReceiver, ATcpqServerThatHangsUpAndComesBackIsHeardAgain) {
  support::LoopbackListener server;
  std::atomic<bool> hung_up{false};
  std::thread serve([&server, &hung_up] {
    // The first instance hears tick 1, then the server hangs up. Every client after that is
    // answered, as LCM's own server answers its clients at once: the looks, the new instance
    // (which hears tick 2 and is kept until the test ends), and the old instance, which liblcm
    // connects once more while destroying it (to unsubscribe).
    int client = support::accept_client(server.fd());
    if (client < 0) return;
    forward_tick(client, 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::close(client);
    hung_up = true;
    std::vector<int> kept;
    for (client = support::accept_client(server.fd()); client >= 0; client = support::accept_client(server.fd())) {
      if (kept.empty()) forward_tick(client, 2);
      kept.push_back(client);
    }
    for (const int c : kept) ::close(c);
  });
  {
    LcmReceiver receiver(server.url());
    EXPECT_EQ(next_tick(receiver), 1);
    EXPECT_EQ(next_tick(receiver), 2) << "nothing heard after the server came back";
    EXPECT_TRUE(hung_up.load());
    EXPECT_EQ(receiver.reconnects(), 1u);
  }
  ::shutdown(server.fd(), SHUT_RDWR);  // wakes an accept still waiting
  serve.join();
  // The old instance went while its server answered: destroyed there and then, not on a thread
  // of its own (one still running when the test ends looks like a leak to the leak checker).
  EXPECT_EQ(hal::lcm_destroys_in_flight(), 0u);
}

// liblcm's instance waits for a tcpq server's handshake without a timeout: against a server that
// queues the connection and never answers, the receiver (and so `sculpt view --lcm`) never
// started. It looks first.
TEST(LcmReceiver, ATcpqServerThatDoesNotHandshakeIsAnErrorNotAWait) {
  support::LoopbackListener server;  // never accepts
  const std::string url = server.url();
  auto making = std::async(std::launch::async, [&url]() -> std::string {
    try {
      LcmReceiver receiver(url);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "made";
  });
  const bool returned = making.wait_for(std::chrono::seconds(3)) == std::future_status::ready;
  EXPECT_TRUE(returned) << "the receiver waited for a server that does not answer";
  server.close();  // refuses the handshake it may be waiting for
  EXPECT_EQ(making.get(), "LCM viewer: no server answered at '" + url + "'");
}

}  // namespace
}  // namespace sculpt::view
