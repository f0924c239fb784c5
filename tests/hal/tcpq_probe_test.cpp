// tcpq_server_answers: a short connect that tells whether a tcpq server is back, without
// liblcm (whose own connect can block for minutes) and without a host-name lookup.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include "sculpt/hal/tcpq_probe.hpp"

namespace sculpt::hal {
namespace {

TEST(TcpqProbe, AnswersOnlyForAListeningIpv4ServerOfATcpqUrl) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(fd, 4), 0);
  ASSERT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const std::string port = std::to_string(ntohs(address.sin_port));

  EXPECT_TRUE(tcpq_server_answers("tcpq://127.0.0.1:" + port, 200));
  EXPECT_TRUE(tcpq_server_answers("tcpq://127.0.0.1:" + port + "?recv_buf_size=1", 200));
  EXPECT_FALSE(tcpq_server_answers("localhost:" + port, 200)) << "not a tcpq URL";
  EXPECT_FALSE(tcpq_server_answers("udpm://127.0.0.1:" + port, 200));
  EXPECT_FALSE(tcpq_server_answers("tcpq://localhost:" + port, 200)) << "a host name is not looked up";
  EXPECT_FALSE(tcpq_server_answers("tcpq://127.0.0.1:0", 200));
  EXPECT_FALSE(tcpq_server_answers("tcpq://127.0.0.1:65536", 200));
  EXPECT_FALSE(tcpq_server_answers("tcpq://127.0.0.1:" + port + "x", 200));
  EXPECT_FALSE(tcpq_server_answers("tcpq://127.0.0.1.1.1.1.1.1.1:" + port, 200));
  ::close(fd);
  EXPECT_FALSE(tcpq_server_answers("tcpq://127.0.0.1:" + port, 200)) << "nothing listens there now";
}

}  // namespace
}  // namespace sculpt::hal
