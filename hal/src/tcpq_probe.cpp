#include "sculpt/hal/tcpq_probe.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>

namespace sculpt::hal {

std::optional<sockaddr_in> tcpq_server_address(std::string_view url) noexcept {
  if (!is_tcpq_url(url)) return std::nullopt;
  std::string_view network = url.substr(kTcpqScheme.size());
  network = network.substr(0, network.find('?'));
  if (network.empty()) network = "127.0.0.1:7700";  // liblcm's default
  const std::size_t colon = network.find(':');
  const std::string_view host = network.substr(0, colon);
  int port = 7700;
  if (colon != std::string_view::npos) {
    const std::string_view digits = network.substr(colon + 1);
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
    if (error != std::errc() || end != digits.data() + digits.size() || port < 1 || port > 65535) return std::nullopt;
  }
  std::array<char, 16> text{};  // "255.255.255.255" and its terminator
  if (host.size() >= text.size()) return std::nullopt;
  host.copy(text.data(), host.size());
  sockaddr_in server{};
  server.sin_family = AF_INET;
  server.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::inet_pton(AF_INET, text.data(), &server.sin_addr) != 1) return std::nullopt;
  return server;
}

std::optional<std::string> tcpq_url_by_address(const std::string& url) {
  if (!is_tcpq_url(url)) return url;
  // tcpq://HOST[:PORT][?OPTIONS]
  const std::size_t begin = kTcpqScheme.size();
  const std::size_t end = std::min(url.find_first_of(":?", begin), url.size());
  const std::string host = url.substr(begin, end - begin);
  in_addr numeric{};
  if (host.empty() || ::inet_pton(AF_INET, host.c_str(), &numeric) == 1) return url;  // an address already
  addrinfo wanted{};
  wanted.ai_family = AF_INET;  // liblcm's tcpq client connects over IPv4 only
  wanted.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &wanted, &found) != 0 || found == nullptr) return std::nullopt;
  std::array<char, INET_ADDRSTRLEN> text{};
  const auto* address = reinterpret_cast<const sockaddr_in*>(found->ai_addr);
  const bool written = ::inet_ntop(AF_INET, &address->sin_addr, text.data(), text.size()) != nullptr;
  ::freeaddrinfo(found);
  if (!written) return std::nullopt;
  return url.substr(0, begin) + text.data() + url.substr(end);
}

bool tcpq_server_answers(std::string_view url, int timeout_ms) noexcept {
  const std::optional<sockaddr_in> server = tcpq_server_address(url);
  if (!server) return false;
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  // Waits for `events` on the socket until the deadline.
  const auto ready = [&](short events) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd wait{fd, events, 0};
    return left.count() > 0 && ::poll(&wait, 1, static_cast<int>(left.count())) == 1 && (wait.revents & events) != 0;
  };
  bool connected = ::connect(fd, reinterpret_cast<const sockaddr*>(&*server), sizeof *server) == 0;
  if (!connected && errno == EINPROGRESS && ready(POLLOUT)) {
    int error = 0;
    socklen_t length = sizeof error;
    connected = ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) == 0 && error == 0;
  }
  // LCM's tcpq handshake: the client's magic and protocol version out, the server's magic back
  // (big-endian words). A server whose kernel queues the connection but whose process does not
  // answer is not answering: liblcm would wait for that reply without a timeout.
  constexpr std::uint32_t kClientMagic = 0x287617fb, kServerMagic = 0x287617fa, kVersion = 0x0100;
  const std::array<std::uint32_t, 2> hello = {htonl(kClientMagic), htonl(kVersion)};
  bool answered = connected && ::send(fd, hello.data(), sizeof hello, MSG_NOSIGNAL) == sizeof hello;
  std::array<std::uint8_t, 8> reply{};
  std::size_t received = 0;
  while (answered && received < reply.size()) {
    const ssize_t n = ready(POLLIN) ? ::recv(fd, reply.data() + received, reply.size() - received, 0) : -1;
    if (n <= 0) answered = false;
    if (n > 0) received += static_cast<std::size_t>(n);
  }
  std::uint32_t magic = 0;
  std::memcpy(&magic, reply.data(), sizeof magic);
  ::close(fd);
  return answered && ntohl(magic) == kServerMagic;
}

}  // namespace sculpt::hal
