// tcpq_server_answers: a short look that tells whether a tcpq server would let liblcm through
// (connect and handshake), without liblcm (which waits for either without a timeout) and
// without a host-name lookup.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>

#include "sculpt/hal/tcpq_probe.hpp"

namespace sculpt::hal {
namespace {

// A loopback listener on a port of the system's choosing, with `backlog`.
struct Listener {
  int fd = -1;
  sockaddr_in address{};
  explicit Listener(int backlog) {
    fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(fd, backlog) != 0 || ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
      throw std::runtime_error("cannot listen on loopback");
    }
  }
  ~Listener() {
    if (fd >= 0) ::close(fd);
  }
  std::string url() const { return "tcpq://127.0.0.1:" + std::to_string(ntohs(address.sin_port)); }
};

// Accepts `count` connections; answers each one's handshake with `magic` when `answer`.
std::thread serve(const Listener& listener, int count, bool answer, std::uint32_t magic = 0x287617fa) {
  return std::thread([fd = listener.fd, count, answer, magic] {
    for (int k = 0; k < count; ++k) {
      const int client = ::accept(fd, nullptr, nullptr);
      if (client < 0) return;
      std::array<std::uint8_t, 8> hello{};
      (void)::recv(client, hello.data(), hello.size(), MSG_WAITALL);
      if (answer) {
        const std::array<std::uint32_t, 2> reply = {htonl(magic), htonl(0x0100)};
        (void)::send(client, reply.data(), sizeof reply, MSG_NOSIGNAL);
      }
      std::array<std::uint8_t, 8> rest{};
      (void)::recv(client, rest.data(), rest.size(), 0);  // until the look hangs up
      ::close(client);
    }
  });
}

TEST(TcpqProbe, TheServerOfATcpqUrlIsAnIpv4AddressAndAPort) {
  const auto server = tcpq_server_address("tcpq://10.1.2.3:7701?recv_buf_size=1");
  ASSERT_TRUE(server.has_value());
  EXPECT_EQ(ntohl(server->sin_addr.s_addr), 0x0a010203u);
  EXPECT_EQ(ntohs(server->sin_port), 7701);
  const auto fallback = tcpq_server_address("tcpq://");
  ASSERT_TRUE(fallback.has_value()) << "liblcm's default server";
  EXPECT_EQ(ntohl(fallback->sin_addr.s_addr), INADDR_LOOPBACK);
  EXPECT_EQ(ntohs(fallback->sin_port), 7700);
  EXPECT_FALSE(tcpq_server_address("localhost:7700")) << "not a tcpq URL";
  EXPECT_FALSE(tcpq_server_address("udpm://127.0.0.1:7700"));
  EXPECT_FALSE(tcpq_server_address("tcpq://localhost:7700")) << "a host name is not looked up";
  EXPECT_FALSE(tcpq_server_address("tcpq://127.0.0.1:0"));
  EXPECT_FALSE(tcpq_server_address("tcpq://127.0.0.1:65536"));
  EXPECT_FALSE(tcpq_server_address("tcpq://127.0.0.1:7700x"));
  EXPECT_FALSE(tcpq_server_address("tcpq://127.0.0.1.1.1.1.1.1.1:7700"));
}

// A host name is looked up once, where a start may wait, and the URL then names the address:
// liblcm's later connects and the looks need no lookup.
TEST(TcpqProbe, AHostNameIsReplacedByItsAddressAndTheRestKept) {
  EXPECT_EQ(tcpq_url_by_address("tcpq://localhost:7700?recv_buf_size=4096"),
            "tcpq://127.0.0.1:7700?recv_buf_size=4096");
  EXPECT_EQ(tcpq_url_by_address("tcpq://localhost"), "tcpq://127.0.0.1");
  EXPECT_EQ(tcpq_url_by_address("tcpq://localhost?recv_buf_size=1"), "tcpq://127.0.0.1?recv_buf_size=1");
  for (const char* same : {"tcpq://", "tcpq://10.1.2.3:7701", "udpm://239.255.76.67:7667?ttl=0", "memq://"}) {
    EXPECT_EQ(tcpq_url_by_address(same), same);
  }
  // An empty label: refused by the resolver itself, without asking a name server.
  EXPECT_EQ(tcpq_url_by_address("tcpq://glove..invalid:7700"), std::nullopt);
}

TEST(TcpqProbe, AServerAnswersWhenItCompletesLcmsHandshake) {
  Listener listener(4);
  std::thread server = serve(listener, 2, true);
  EXPECT_TRUE(tcpq_server_answers(listener.url(), 1000));
  EXPECT_TRUE(tcpq_server_answers(listener.url() + "?recv_buf_size=1", 1000));
  server.join();
  EXPECT_FALSE(tcpq_server_answers("tcpq://localhost:" + std::to_string(ntohs(listener.address.sin_port)), 200))
      << "a host name is not looked up";
  ::close(listener.fd);
  listener.fd = -1;
  EXPECT_FALSE(tcpq_server_answers(listener.url(), 200)) << "nothing listens there now";
}

// A server process that is stopped or hung still has its connections queued by the kernel, and
// liblcm then waits for its handshake for ever; one that answers with the wrong words is not
// LCM. Neither answers, and the look gives up at its timeout.
TEST(TcpqProbe, AServerThatDoesNotCompleteTheHandshakeDoesNotAnswer) {
  {
    Listener listener(4);  // queues connections, never accepts them
    const auto start = std::chrono::steady_clock::now();
    EXPECT_FALSE(tcpq_server_answers(listener.url(), 200));
    const auto took = std::chrono::steady_clock::now() - start;
    EXPECT_GE(took, std::chrono::milliseconds(150));
    EXPECT_LT(took, std::chrono::seconds(2));
  }
  {
    Listener listener(4);
    std::thread server = serve(listener, 1, false);  // accepts, reads, says nothing
    EXPECT_FALSE(tcpq_server_answers(listener.url(), 200));
    server.join();
  }
  {
    Listener listener(4);
    std::thread server = serve(listener, 1, true, 0x12345678);
    EXPECT_FALSE(tcpq_server_answers(listener.url(), 1000));
    server.join();
  }
  {
    // A full queue: Linux drops the connects it cannot queue, as a host gone from the network
    // answers none.
    Listener listener(0);
    const int queued = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    ASSERT_EQ(::connect(queued, reinterpret_cast<const sockaddr*>(&listener.address), sizeof listener.address), 0);
    EXPECT_FALSE(tcpq_server_answers(listener.url(), 200));
    ::close(queued);
  }
}

}  // namespace
}  // namespace sculpt::hal
