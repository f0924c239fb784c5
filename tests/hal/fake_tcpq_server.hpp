#pragma once
// The server side of LCM's tcpq transport, played by a test: a loopback listener, the
// handshake, and the words of a published message. liblcm's tcpq client connects, sends its
// magic and protocol version, and waits for the server's; then it sends its subscriptions and
// publications, and the server forwards publications (big-endian words throughout).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <stdexcept>
#include <string>

#include "support/eventually.hpp"

namespace sculpt::hal::testing_support {

// A listening socket on a free loopback port (backlog 1).
class LoopbackListener {
 public:
  LoopbackListener() : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(fd_, 1) != 0 ||
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
      throw std::runtime_error("cannot listen on loopback");
    }
    port_ = ntohs(address.sin_port);
  }
  ~LoopbackListener() { close(); }
  LoopbackListener(const LoopbackListener&) = delete;
  LoopbackListener& operator=(const LoopbackListener&) = delete;
  int fd() const { return fd_; }
  std::uint16_t port() const { return port_; }
  std::string url() const { return "tcpq://127.0.0.1:" + std::to_string(port_); }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
  std::uint16_t port_ = 0;
};

// A listening socket on a given loopback port (a server back after it went away), or -1.
inline int listen_on(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int yes = 1;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(port);
  if (fd < 0 || ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes) != 0 ||
      ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(fd, 4) != 0) {
    if (fd >= 0) ::close(fd);
    return -1;
  }
  return fd;
}

// The handshake on an accepted connection, then the client's first words (a subscription or a
// publication). False when the client hung up instead (tcpq_server_answers' look, which
// handshakes and closes).
inline bool serve_handshake(int client) {
  std::array<std::uint8_t, 8> hello{};
  if (::recv(client, hello.data(), hello.size(), MSG_WAITALL) != static_cast<ssize_t>(hello.size())) return false;
  const std::array<std::uint8_t, 8> answer = {0x28, 0x76, 0x17, 0xfa, 0x00, 0x00, 0x01, 0x00};
  (void)::send(client, answer.data(), answer.size(), MSG_NOSIGNAL);
  std::array<std::uint8_t, 64> first{};
  return ::recv(client, first.data(), first.size(), 0) > 0;
}

// Accepts clients until one sends something after its handshake, and returns it (or -1 when
// the listener is shut): the looks, which come first, hang up after the handshake.
inline int accept_client(int listener) {
  for (;;) {
    const int client = ::accept(listener, nullptr, nullptr);
    if (client < 0) return -1;
    if (serve_handshake(client)) return client;
    ::close(client);
  }
}

inline void send_word(int client, std::uint32_t word) {
  const std::uint32_t big = htonl(word);
  (void)::send(client, &big, sizeof big, MSG_NOSIGNAL);
}

// What `device.start()` (a glove source or a haptic sink on `server`'s URL) said: its error's
// text, or "started"; "still starting after 3 s" when it had not returned by then (the server
// is then closed, which refuses the connect or handshake it waited on, so the call ends).
template <typename Device>
std::string start_within_3_s(Device& device, LoopbackListener& server) {
  auto starting = std::async(std::launch::async, [&device]() -> std::string {
    try {
      device.start();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "started";
  });
  const bool returned = starting.wait_for(std::chrono::seconds(3)) == std::future_status::ready;
  server.close();
  const std::string said = starting.get();
  return returned ? said : "still starting after 3 s";
}

// support/eventually.hpp with these tests' patience: up to 10 s, as they wait on looks a second
// apart and a loaded machine is slow at times.
inline bool eventually_within_10s(const std::function<bool()>& done) {
  return test::eventually(done, std::chrono::seconds(10), std::chrono::milliseconds(5));
}

}  // namespace sculpt::hal::testing_support
